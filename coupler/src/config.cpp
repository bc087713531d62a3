#include "coflow/config.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace coflow::config {

double Distribution::mean() const {
  switch (kind) {
    case Kind::fixed: return a;
    case Kind::uniform: return 0.5 * (a + b);
    case Kind::lognormal: return a;
  }
  return a;
}

// ---------------------------------------------------------------- messages --

std::string Problem::format() const {
  std::string where = file;
  if (line > 0) where += fmt::format(":{}:{}", line, column);
  if (path.empty()) return fmt::format("{}: {}", where, message);
  return fmt::format("{}: {}: {}", where, path, message);
}

static std::string join_problems(const std::vector<Problem>& problems) {
  std::string s;
  for (const auto& p : problems) {
    if (!s.empty()) s += '\n';
    s += p.format();
  }
  return s;
}

ConfigError::ConfigError(std::vector<Problem> problems)
    : std::runtime_error(join_problems(problems)), problems_(std::move(problems)) {}

std::string closest(std::string_view word, const std::vector<std::string>& candidates) {
  // Optimal string alignment: edits plus adjacent transpositions ("D3Q91" is one
  // edit from "D3Q19"), which is how most typos look.
  auto distance = [](std::string_view a, std::string_view b) {
    const std::size_t n = a.size(), m = b.size();
    std::vector<std::size_t> d((n + 1) * (m + 1));
    auto at = [&](std::size_t i, std::size_t j) -> std::size_t& { return d[i * (m + 1) + j]; };
    for (std::size_t i = 0; i <= n; ++i) at(i, 0) = i;
    for (std::size_t j = 0; j <= m; ++j) at(0, j) = j;
    for (std::size_t i = 1; i <= n; ++i)
      for (std::size_t j = 1; j <= m; ++j) {
        const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
        at(i, j) = std::min({at(i - 1, j) + 1, at(i, j - 1) + 1, at(i - 1, j - 1) + cost});
        if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
          at(i, j) = std::min(at(i, j), at(i - 2, j - 2) + 1);
      }
    return at(n, m);
  };
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

// ------------------------------------------------------------------- text --

namespace {

std::string number_text(double x) {
  if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 1e15)
    return fmt::format("{}", static_cast<long long>(x));
  return fmt::format("{}", x);
}

template <class A>
std::string list_text(const A& a) {
  std::string s = "[";
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (i) s += ", ";
    if constexpr (std::is_same_v<typename A::value_type, bool>)
      s += a[i] ? "true" : "false";
    else if constexpr (std::is_same_v<typename A::value_type, std::string>)
      s += a[i];
    else
      s += number_text(static_cast<double>(a[i]));
  }
  return s + "]";
}

struct TypeName {
  std::string operator()(double*) const { return "number"; }
  std::string operator()(int*) const { return "integer"; }
  std::string operator()(std::uint64_t*) const { return "integer"; }
  std::string operator()(bool*) const { return "bool"; }
  std::string operator()(std::string*) const { return "string"; }
  std::string operator()(Vec3*) const { return "[x, y, z]"; }
  std::string operator()(Int3*) const { return "[i, j, k]"; }
  std::string operator()(Bool3*) const { return "[bool, bool, bool]"; }
  std::string operator()(StringList*) const { return "list of strings"; }
  std::string operator()(AutoDouble*) const { return "number or auto"; }
  std::string operator()(AutoInt3*) const { return "auto or [i, j, k]"; }
  std::string operator()(Numbers*) const { return "number or list"; }
  std::string operator()(Distribution*) const {
    return "number | {uniform: {min, max}} | {lognormal: {mean, std}}";
  }
  std::string operator()(FilePath*) const { return "file path"; }
};

}  // namespace

std::string to_text(const ValueRef& ref) {
  return std::visit(
      [](auto* p) -> std::string {
        using T = std::remove_pointer_t<decltype(p)>;
        if constexpr (std::is_same_v<T, double> || std::is_same_v<T, int> ||
                      std::is_same_v<T, std::uint64_t>)
          return number_text(static_cast<double>(*p));
        else if constexpr (std::is_same_v<T, bool>)
          return *p ? "true" : "false";
        else if constexpr (std::is_same_v<T, std::string>)
          return *p;
        else if constexpr (std::is_same_v<T, FilePath>)
          return p->path;
        else if constexpr (std::is_same_v<T, AutoDouble>)
          return p->is_auto ? "auto" : number_text(p->value);
        else if constexpr (std::is_same_v<T, AutoInt3>)
          return p->is_auto ? "auto" : list_text(p->value);
        else if constexpr (std::is_same_v<T, Numbers>)
          return p->values.size() == 1 ? number_text(p->values[0]) : list_text(p->values);
        else if constexpr (std::is_same_v<T, Distribution>) {
          switch (p->kind) {
            case Distribution::Kind::fixed: return number_text(p->a);
            case Distribution::Kind::uniform:
              return fmt::format("{{uniform: {{min: {}, max: {}}}}}", p->a, p->b);
            case Distribution::Kind::lognormal:
              return fmt::format("{{lognormal: {{mean: {}, std: {}}}}}", p->a, p->b);
          }
          return "";
        } else
          return list_text(*p);
      },
      ref);
}

// ------------------------------------------------------------------ rules --

namespace {

// Calls f on every number a value holds (none for strings and `auto`).
template <class F>
void each_number(const ValueRef& ref, F&& f) {
  std::visit(
      [&](auto* p) {
        using T = std::remove_pointer_t<decltype(p)>;
        if constexpr (std::is_same_v<T, double> || std::is_same_v<T, int> ||
                      std::is_same_v<T, std::uint64_t>)
          f(static_cast<double>(*p));
        else if constexpr (std::is_same_v<T, Vec3> || std::is_same_v<T, Int3>)
          for (auto x : *p) f(static_cast<double>(x));
        else if constexpr (std::is_same_v<T, AutoDouble>) {
          if (!p->is_auto) f(p->value);
        } else if constexpr (std::is_same_v<T, AutoInt3>) {
          if (!p->is_auto)
            for (auto x : p->value) f(static_cast<double>(x));
        } else if constexpr (std::is_same_v<T, Numbers>) {
          for (auto x : p->values) f(x);
        } else if constexpr (std::is_same_v<T, Distribution>) {
          f(p->a);
          if (p->kind != Distribution::Kind::fixed) f(p->b);
        }
      },
      ref);
}

Rule numeric_rule(std::string text, std::function<bool(double)> ok) {
  Rule r;
  r.text = text;
  r.test = [text, ok](const ValueRef& ref) {
    std::string err;
    each_number(ref, [&](double x) {
      if (err.empty() && !ok(x))
        err = fmt::format("must be {} (got {})", text, to_text(ref));
    });
    return err;
  };
  return r;
}

}  // namespace

Rule greater(double b) { return numeric_rule("> " + number_text(b), [b](double x) { return x > b; }); }
Rule at_least(double b) { return numeric_rule(">= " + number_text(b), [b](double x) { return x >= b; }); }
Rule below(double b) { return numeric_rule("< " + number_text(b), [b](double x) { return x < b; }); }
Rule positive() { return numeric_rule("> 0", [](double x) { return x > 0; }); }
Rule non_negative() { return numeric_rule(">= 0", [](double x) { return x >= 0; }); }
Rule in_range(double lo, double hi) {
  return numeric_rule(fmt::format("in [{}, {}]", number_text(lo), number_text(hi)),
                      [lo, hi](double x) { return x >= lo && x <= hi; });
}

Rule one_of(std::vector<std::string> names) {
  Rule r;
  r.text = fmt::format("one of: {}", fmt::join(names, " | "));
  r.test = [names](const ValueRef& ref) -> std::string {
    const auto* s = std::get_if<std::string*>(&ref);
    if (!s) return {};
    if (std::find(names.begin(), names.end(), **s) != names.end()) return {};
    std::string msg = fmt::format("unknown value '{}'", **s);
    const std::string near = closest(**s, names);
    if (!near.empty()) msg += fmt::format("; did you mean '{}'?", near);
    return msg + fmt::format(" (valid: {})", fmt::join(names, ", "));
  };
  return r;
}

Rule each_one_of(std::vector<std::string> names) {
  Rule r;
  r.text = fmt::format("each one of: {}", fmt::join(names, " | "));
  r.test = [names](const ValueRef& ref) -> std::string {
    const auto* l = std::get_if<StringList*>(&ref);
    if (!l) return {};
    for (auto it = (**l).begin(); it != (**l).end(); ++it) {
      const std::string& s = *it;
      if (std::find((**l).begin(), it, s) != it) return fmt::format("'{}' is listed twice; list it once", s);
      if (std::find(names.begin(), names.end(), s) != names.end()) continue;
      std::string msg = fmt::format("unknown entry '{}'", s);
      const std::string near = closest(s, names);
      if (!near.empty()) msg += fmt::format("; did you mean '{}'?", near);
      return msg + fmt::format(" (valid: {})", fmt::join(names, ", "));
    }
    return {};
  };
  return r;
}

// ---------------------------------------------------------------- parsing --

namespace {

// A finite number: YAML's .inf and .nan are refused (an infinite end time or
// timeout would pass "> 0" and then overflow the window count or disable
// every deadline).
bool scalar_double(const YAML::Node& n, double& out) {
  if (!n.IsScalar()) return false;
  try {
    const double x = n.as<double>();
    if (!std::isfinite(x)) return false;
    out = x;
    return true;
  } catch (const YAML::Exception&) {
    return false;
  }
}

// Whether a scalar is YAML's .inf, -.inf or .nan (a number, but not a finite one).
bool non_finite(const YAML::Node& n) {
  if (!n.IsScalar()) return false;
  try {
    return !std::isfinite(n.as<double>());
  } catch (const YAML::Exception&) {
    return false;
  }
}

// The text value() gives a required key the file leaves out (and the test
// for it: other checks may say "missing required key" in other words).
constexpr const char* kMissingKey = "missing required key";
bool is_missing_key(const std::string& m) {
  return m.starts_with(std::string(kMissingKey) + " (") ||
         m.starts_with(std::string(kMissingKey) + "; add '");
}

// Whether the integral value d lies outside I (its max as a double rounds up
// to 2^digits, itself out of range: compare against that power exactly).
template <class I>
bool integer_out_of_range(double d) {
  return d >= std::ldexp(1.0, std::numeric_limits<I>::digits) ||
         d < static_cast<double>(std::numeric_limits<I>::lowest());
}

template <class I>
bool scalar_int(const YAML::Node& n, I& out) {
  if (!n.IsScalar()) return false;
  try {
    out = n.as<I>();
    return true;
  } catch (const YAML::Exception&) {
    // Accept integral floating literals such as 1e4.
    double d = 0;
    if (scalar_double(n, d) && std::isfinite(d) && d == std::floor(d) && !integer_out_of_range<I>(d)) {
      out = static_cast<I>(d);
      return true;
    }
    return false;
  }
}

// Why a scalar that is not a usable number of this kind fails, when the
// reason is not its type: empty (null), not finite, or beyond the range of
// the integer asked for. "" when it is simply not a number.
template <class I = double>
std::string number_range_problem(const YAML::Node& n) {
  if (n.IsNull()) return "is empty (null): give a value";
  if (!n.IsScalar()) return "";
  const std::string t = n.Scalar();
  char* end = nullptr;
  errno = 0;
  const double d = std::strtod(t.c_str(), &end);
  if (end == t.c_str() || *end != '\0')
    return non_finite(n) ? fmt::format("must be finite (got '{}')", t) : "";
  if (errno == ERANGE && std::abs(d) > 1.0)
    return fmt::format("is beyond the range of a double (got '{}')", t);
  if (!std::isfinite(d)) return fmt::format("must be finite (got '{}')", t);
  if constexpr (std::is_integral_v<I>) {
    if (d != std::floor(d) || (std::is_unsigned_v<I> && d < 0.0)) return "";  // the caller's message says it
    if (integer_out_of_range<I>(d))
      return fmt::format("is out of range: {} to {} (got '{}')", std::numeric_limits<I>::lowest(),
                         std::numeric_limits<I>::max(), t);
  }
  return "";
}

template <class T, std::size_t N, class Parse>
std::string parse_array(const YAML::Node& n, std::array<T, N>& out, Parse parse,
                        const char* what, const char* one) {
  if (!n.IsSequence() || n.size() != N)
    return fmt::format("expected a list of {} {} like [{}]", N, what,
                       N == 3 ? (std::is_same_v<T, bool> ? "true, false, false" : "1, 2, 3") : "...");
  std::array<T, N> tmp{};
  for (std::size_t i = 0; i < N; ++i)
    if (!parse(n[i], tmp[i])) {
      if (const std::string why = number_range_problem<T>(n[i]); !why.empty() && !std::is_same_v<T, bool>)
        return fmt::format("entry {} {}", i, why);
      return fmt::format("entry {} must be {} (got '{}')", i, one,
                         n[i].IsScalar() ? n[i].Scalar() : "a collection");
    }
  out = tmp;
  return {};
}

// Returns an error message, or "" on success.
struct Parser {
  const YAML::Node& n;
  std::string operator()(double* p) const {
    if (scalar_double(n, *p)) return "";
    if (const std::string why = number_range_problem(n); !why.empty()) return why;
    return fmt::format("expected a number (got '{}')", text());
  }
  std::string operator()(int* p) const {
    if (scalar_int(n, *p)) return "";
    if (const std::string why = number_range_problem<int>(n); !why.empty()) return why;
    return fmt::format("expected an integer (got '{}')", text());
  }
  std::string operator()(std::uint64_t* p) const {
    if (scalar_int(n, *p)) return "";
    if (const std::string why = number_range_problem<std::uint64_t>(n); !why.empty()) return why;
    return fmt::format("expected a non-negative integer (got '{}')", text());
  }
  std::string operator()(bool* p) const {
    if (n.IsScalar()) {
      try {
        *p = n.as<bool>();
        return {};
      } catch (const YAML::Exception&) {
      }
    }
    return fmt::format("expected true or false (got '{}')", text());
  }
  std::string operator()(std::string* p) const {
    if (n.IsNull()) return "is empty (null): give a value";
    if (!n.IsScalar()) return "expected a single word or string, not a list or mapping";
    *p = n.Scalar();
    return {};
  }
  std::string operator()(FilePath* p) const {
    if (!n.IsScalar() || n.Scalar().empty()) return "expected a file name";
    p->path = n.Scalar();
    return {};
  }
  std::string operator()(Vec3* p) const {
    return parse_array(n, *p, [](const YAML::Node& x, double& v) { return scalar_double(x, v); },
                       "numbers", "a number");
  }
  std::string operator()(Int3* p) const {
    return parse_array(n, *p, [](const YAML::Node& x, int& v) { return scalar_int(x, v); },
                       "integers", "an integer");
  }
  std::string operator()(Bool3* p) const {
    return parse_array(
        n, *p,
        [](const YAML::Node& x, bool& v) {
          if (!x.IsScalar()) return false;
          try {
            v = x.as<bool>();
            return true;
          } catch (const YAML::Exception&) {
            return false;
          }
        },
        "booleans", "true or false");
  }
  std::string operator()(StringList* p) const {
    if (!n.IsSequence()) return "expected a list like [a, b]";
    StringList tmp;
    for (const auto& x : n) {
      if (!x.IsScalar()) return "every entry must be a word";
      tmp.push_back(x.Scalar());
    }
    *p = std::move(tmp);
    return {};
  }
  std::string operator()(AutoDouble* p) const {
    if (n.IsScalar() && n.Scalar() == "auto") {
      p->is_auto = true;
      return {};
    }
    double v = 0;
    if (!scalar_double(n, v))
      return fmt::format("expected a {}number or 'auto' (got '{}')", non_finite(n) ? "finite " : "", text());
    p->is_auto = false;
    p->value = v;
    return {};
  }
  std::string operator()(AutoInt3* p) const {
    if (n.IsScalar() && n.Scalar() == "auto") {
      p->is_auto = true;
      return {};
    }
    Int3 v{};
    std::string e = (*this)(&v);
    if (!e.empty())
      return e.starts_with("expected ") ? "expected 'auto' or " + e.substr(std::string("expected ").size())
                                        : e + " (or give 'auto')";
    p->is_auto = false;
    p->value = v;
    return {};
  }
  std::string operator()(Numbers* p) const {
    double v = 0;
    if (scalar_double(n, v)) {
      p->values = {v};
      return {};
    }
    if (!n.IsSequence()) return fmt::format("expected a number or a list of numbers (got '{}')", text());
    std::vector<double> tmp;
    for (const auto& x : n) {
      if (!scalar_double(x, v)) return "every entry must be a number";
      tmp.push_back(v);
    }
    p->values = std::move(tmp);
    return {};
  }
  std::string operator()(Distribution* p) const {
    double v = 0;
    if (scalar_double(n, v)) {
      *p = Distribution{Distribution::Kind::fixed, v, 0.0};
      return {};
    }
    const char* usage =
        "expected a number, {uniform: {min: A, max: B}} or {lognormal: {mean: M, std: S}}";
    if (!n.IsMap() || n.size() != 1) return usage;
    const std::string kind = n.begin()->first.Scalar();
    const YAML::Node body = n.begin()->second;
    const bool uni = kind == "uniform", logn = kind == "lognormal";
    if ((!uni && !logn) || !body.IsMap() || body.size() != 2) return usage;
    const char* k1 = uni ? "min" : "mean";
    const char* k2 = uni ? "max" : "std";
    double a = 0, b = 0;
    if (!body[k1] || !body[k2] || !scalar_double(body[k1], a) || !scalar_double(body[k2], b))
      return usage;
    if (uni && !(b > a)) return fmt::format("uniform: max must be > min (got min {} max {})", a, b);
    *p = Distribution{uni ? Distribution::Kind::uniform : Distribution::Kind::lognormal, a, b};
    return {};
  }
  std::string text() const {
    if (n.IsScalar()) return n.Scalar();
    if (n.IsSequence()) return "a list";
    if (n.IsMap()) return "a mapping";
    return "nothing";
  }
};

YAML::Node to_yaml(const ValueRef& ref) {
  return std::visit(
      [](auto* p) -> YAML::Node {
        using T = std::remove_pointer_t<decltype(p)>;
        YAML::Node n;
        if constexpr (std::is_same_v<T, AutoDouble>) {
          n = p->is_auto ? YAML::Node("auto") : YAML::Node(fmt::format("{}", p->value));
        } else if constexpr (std::is_same_v<T, AutoInt3>) {
          if (p->is_auto) {
            n = "auto";
          } else {
            for (int x : p->value) n.push_back(x);
            n.SetStyle(YAML::EmitterStyle::Flow);
          }
        } else if constexpr (std::is_same_v<T, Numbers>) {
          if (p->values.size() == 1) {
            n = fmt::format("{}", p->values[0]);
          } else {
            for (double x : p->values) n.push_back(fmt::format("{}", x));
            n.SetStyle(YAML::EmitterStyle::Flow);
          }
        } else if constexpr (std::is_same_v<T, Distribution>) {
          if (p->kind == Distribution::Kind::fixed) {
            n = p->a;
          } else if (p->kind == Distribution::Kind::uniform) {
            n["uniform"]["min"] = p->a;
            n["uniform"]["max"] = p->b;
            n.SetStyle(YAML::EmitterStyle::Flow);
          } else {
            n["lognormal"]["mean"] = p->a;
            n["lognormal"]["std"] = p->b;
            n.SetStyle(YAML::EmitterStyle::Flow);
          }
        } else if constexpr (std::is_same_v<T, Vec3> || std::is_same_v<T, Int3> ||
                             std::is_same_v<T, Bool3> || std::is_same_v<T, StringList>) {
          n = YAML::Node(YAML::NodeType::Sequence);
          for (const auto& x : *p) {
            if constexpr (std::is_same_v<typename T::value_type, double>)
              n.push_back(fmt::format("{}", x));
            else
              n.push_back(static_cast<typename T::value_type>(x));
          }
          n.SetStyle(YAML::EmitterStyle::Flow);
        } else if constexpr (std::is_same_v<T, FilePath>) {
          n = p->path;
        } else if constexpr (std::is_same_v<T, double>) {
          n = fmt::format("{}", *p);  // shortest text that reads back to the same double
        } else {
          n = *p;
        }
        return n;
      },
      ref);
}

}  // namespace

// ----------------------------------------------------------------- Reader --

struct Reader::Shared {
  std::string file;
  std::vector<Problem> problems;
  bool quiet = false;  // cross-key checks silenced (quiet_cross_checks)
};

Reader::Reader(YAML::Node node, std::string file, std::string path)
    : node_(node),
      anchor_(node),
      shared_(std::make_shared<Shared>()),
      path_(std::move(path)),
      out_(YAML::NodeType::Map) {
  shared_->file = std::move(file);
  if (node_ && !node_.IsNull() && !node_.IsMap())
    problem_at(node_, path_, "expected a mapping of keys to values");
  check_duplicates();
}

Reader::Reader(YAML::Node node, std::shared_ptr<Shared> shared, std::string path, YAML::Node out)
    : node_(std::move(node)), shared_(std::move(shared)), path_(std::move(path)), out_(std::move(out)) {
  check_duplicates();
}

Reader::~Reader() = default;

const std::vector<Problem>& Reader::problems() const { return shared_->problems; }
std::size_t Reader::problem_count() const {
  return shared_->problems.size();
}
bool Reader::problems_since(std::size_t since, const std::vector<std::string>& paths) const {
  const auto& list = shared_->problems;
  for (std::size_t i = since; i < list.size(); ++i)
    if (std::find(paths.begin(), paths.end(), list[i].path) != paths.end()) return true;
  return false;
}
void Reader::quiet_cross_checks() {
  shared_->quiet = true;
}

void Reader::check() const {
  if (!shared_->problems.empty()) throw ConfigError(shared_->problems);
}

YAML::Node Reader::resolved() const { return out_; }

std::string Reader::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

void Reader::problem_at(const YAML::Node& where, const std::string& path, const std::string& msg) {
  Problem p;
  p.file = shared_->file;
  if (where && where.Mark().line >= 0 && !where.Mark().is_null()) {
    p.line = where.Mark().line + 1;
    p.column = where.Mark().column + 1;
  } else if (node_ && !node_.IsNull() && !node_.Mark().is_null()) {
    p.line = node_.Mark().line + 1;
    p.column = node_.Mark().column + 1;
  } else if (anchor_ && !anchor_.Mark().is_null()) {
    p.line = anchor_.Mark().line + 1;
    p.column = anchor_.Mark().column + 1;
  }
  p.path = path;
  p.message = msg;
  shared_->problems.push_back(std::move(p));
}

void Reader::check_duplicates() {
  if (!node_ || !node_.IsMap()) return;
  std::vector<std::pair<std::string, int>> seen;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (!it->first.IsScalar()) {
      problem_at(it->first, path_, "keys must be plain words");
      continue;
    }
    const std::string k = it->first.Scalar();
    auto prev = std::find_if(seen.begin(), seen.end(), [&](auto& s) { return s.first == k; });
    if (prev != seen.end())
      problem_at(it->first, key_path(k),
                 fmt::format("duplicate key (first given on line {}); keep only one", prev->second));
    else
      seen.emplace_back(k, it->first.Mark().line + 1);
  }
}

bool Reader::given(std::string_view key) const {
  return node_ && node_.IsMap() && node_[std::string(key)].IsDefined();
}

void Reader::value(const Key& key, ValueRef ref) {
  const std::string name(key.name);
  visited_.push_back(name);
  const std::string path = key_path(name);
  if (!given(name)) {
    if (key.required) {
      std::string msg = kMissingKey;
      if (!key.doc.empty()) msg += fmt::format(" ({})", key.doc);
      msg += fmt::format("; add '{}: <{}>'", name, std::visit(TypeName{}, ref));
      problem_at(node_, path, msg);
    }
    // An optional list left empty has no default to write down.
    if (const auto* nums = std::get_if<Numbers*>(&ref); nums && (*nums)->values.empty()) return;
    if (const auto* f = std::get_if<FilePath*>(&ref); f && (*f)->path.empty()) return;
    out_[name] = to_yaml(ref);
    return;
  }
  const YAML::Node n = node_[name];
  const std::string err = std::visit(Parser{n}, ref);
  if (auto* f = std::get_if<FilePath*>(&ref); f && err.empty() && (*f)->path[0] != '/')
    (*f)->path = std::filesystem::weakly_canonical(std::filesystem::path(base_dir()) / (*f)->path).string();
  if (!err.empty()) {
    problem_at(n, path, err);
  } else if (key.rule.test) {
    const std::string bad = key.rule.test(ref);
    if (!bad.empty()) problem_at(n, path, bad);
  }
  out_[name] = to_yaml(ref);
}

Reader Reader::child(YAML::Node node, std::string_view name, YAML::Node out) const {
  Reader r(std::move(node), shared_, key_path(name), std::move(out));
  if (!r.node_ || r.node_.IsNull()) r.node_ = YAML::Node();  // absent: defaults only
  r.anchor_ = (node_ && !node_.IsNull()) ? node_ : anchor_;
  return r;
}

void Reader::section(std::string_view name, std::string_view doc,
                     const std::function<void(Visitor&)>& body, bool* present) {
  const std::string k(name);
  visited_.push_back(k);
  const bool here = given(k) && !node_[k].IsNull();
  if (present) *present = here;
  YAML::Node sub = here ? node_[k] : YAML::Node();
  if (here && !sub.IsMap()) {
    problem_at(sub, key_path(k), "expected a mapping (indented 'key: value' lines)");
    return;
  }
  YAML::Node out(YAML::NodeType::Map);
  Reader r = child(sub, k, out);
  const std::size_t before = shared_->problems.size();
  body(r);
  r.finish();
  if (!here) collapse_missing(before, key_path(k));
  if (here || present == nullptr) out_[k] = out;
}

// A section left out whose required keys each said "missing required key":
// one line for the section instead, naming its keys.
void Reader::collapse_missing(std::size_t first, const std::string& path) {
  auto& list = shared_->problems;
  const std::string prefix = path + ".";
  std::vector<std::string> keys;
  for (std::size_t i = first; i < list.size(); ++i) {
    const Problem& p = list[i];
    if (p.path.rfind(prefix, 0) != 0 || !is_missing_key(p.message)) return;  // another kind: keep all
    keys.push_back(p.path.substr(prefix.size()));
  }
  if (keys.size() < 2) return;
  Problem one = list[first];
  one.path = path;
  one.message = fmt::format("missing required section; add '{}: {{{}: ...}}'",
                            path.substr(path.rfind('.') + 1), fmt::join(keys, ": ..., "));
  list.resize(first);
  list.push_back(one);
}

void Reader::entries(std::string_view name, std::string_view doc,
                     const std::function<void(const std::string&, Visitor&)>& body,
                     const std::vector<std::string>& allowed) {
  const std::string k(name);
  visited_.push_back(k);
  if (!given(k) || node_[k].IsNull()) return;
  YAML::Node m = node_[k];
  if (!m.IsMap()) {
    problem_at(m, key_path(k), "expected a mapping of names to settings");
    return;
  }
  Reader holder = child(m, k, YAML::Node(YAML::NodeType::Map));  // duplicate check
  YAML::Node out(YAML::NodeType::Map);
  for (auto it = m.begin(); it != m.end(); ++it) {
    const std::string entry = it->first.Scalar();
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), entry) == allowed.end()) {
      std::string msg = fmt::format("unknown name '{}'", entry);
      const std::string near = closest(entry, allowed);
      if (!near.empty()) msg += fmt::format("; did you mean '{}'?", near);
      problem_at(it->first, holder.key_path(entry),
                 msg + fmt::format(" (valid: {})", fmt::join(allowed, ", ")));
      continue;
    }
    if (!it->second.IsMap()) {
      problem_at(it->second, holder.key_path(entry), "expected a mapping of settings");
      continue;
    }
    YAML::Node eo(YAML::NodeType::Map);
    Reader r = holder.child(it->second, entry, eo);
    body(entry, r);
    r.finish();
    out[entry] = eo;
  }
  out_[k] = out;
}

void Reader::list(std::string_view name, std::string_view doc,
                  const std::function<void(Visitor&)>& body) {
  const std::string k(name);
  visited_.push_back(k);
  if (!given(k) || node_[k].IsNull()) return;
  YAML::Node s = node_[k];
  if (!s.IsSequence()) {
    problem_at(s, key_path(k), "expected a list (lines starting with '- ')");
    return;
  }
  YAML::Node out(YAML::NodeType::Sequence);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const std::string item = fmt::format("{}[{}]", k, i);
    if (!s[i].IsMap()) {
      problem_at(s[i], key_path(item), "expected a mapping of settings");
      continue;
    }
    YAML::Node io(YAML::NodeType::Map);
    Reader r = child(s[i], item, io);
    body(r);
    r.finish();
    out.push_back(io);
  }
  out_[k] = out;
}

void Reader::choices(std::string_view name, std::string_view doc,
                     const std::vector<Alternative>& alternatives) {
  const std::string k(name);
  visited_.push_back(k);
  if (!given(k) || node_[k].IsNull()) return;
  YAML::Node s = node_[k];
  std::vector<std::string> names;
  for (const auto& a : alternatives) names.push_back(a.name);
  if (!s.IsSequence()) {
    problem_at(s, key_path(k), fmt::format("expected a list of items, each one of: {}",
                                           fmt::join(names, ", ")));
    return;
  }
  YAML::Node out(YAML::NodeType::Sequence);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const std::string item = fmt::format("{}[{}]", k, i);
    if (!s[i].IsMap() || s[i].size() != 1) {
      problem_at(s[i], key_path(item),
                 fmt::format("each item must be a single key, one of: {}", fmt::join(names, ", ")));
      continue;
    }
    const std::string which = s[i].begin()->first.Scalar();
    auto alt = std::find_if(alternatives.begin(), alternatives.end(),
                            [&](const Alternative& a) { return a.name == which; });
    if (alt == alternatives.end()) {
      std::string msg = fmt::format("unknown item '{}'", which);
      const std::string near = closest(which, names);
      if (!near.empty()) msg += fmt::format("; did you mean '{}'?", near);
      problem_at(s[i].begin()->first, key_path(item),
                 msg + fmt::format(" (valid: {})", fmt::join(names, ", ")));
      continue;
    }
    YAML::Node body = s[i].begin()->second;
    if (!body.IsMap()) {
      problem_at(body, key_path(item + "." + which), "expected a mapping of settings");
      continue;
    }
    YAML::Node io(YAML::NodeType::Map);
    Reader r = child(body, item + "." + which, io);
    alt->body(r);
    r.finish();
    YAML::Node wrapped;
    wrapped[which] = io;
    out.push_back(wrapped);
  }
  out_[k] = out;
}

void Reader::fail(std::string_view key, const std::string& message) {
  if (shared_->quiet) return;
  const std::string k(key);
  // A dotted key (a.b.c) points into subsections: report the deepest node given.
  // (YAML::Node's operator= writes into the node: move with reset().)
  YAML::Node where;
  where.reset(node_);
  std::istringstream parts(k);
  for (std::string part; !k.empty() && std::getline(parts, part, '.');) {
    const YAML::Node& here = where;
    // An item of a list: run.output.probes[1].point
    const auto open = part.find('[');
    const std::string name = part.substr(0, open);
    if (!here.IsMap() || !here[name]) break;
    where.reset(here[name]);
    if (open == std::string::npos) continue;
    const std::size_t i = std::stoul(part.substr(open + 1));
    const YAML::Node& list = where;
    if (!list.IsSequence() || i >= list.size()) break;
    where.reset(list[i]);
  }
  problem_at(where, k.empty() ? path_ : key_path(k), message);
}

void Reader::accept_other_keys() { accept_other_ = true; }

std::string Reader::base_dir() const {
  const auto slash = shared_->file.find_last_of('/');
  return slash == std::string::npos ? "." : shared_->file.substr(0, slash);
}

void Reader::finish() {
  if (finished_) return;
  finished_ = true;
  if (!node_ || !node_.IsMap()) return;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (!it->first.IsScalar()) continue;
    const std::string k = it->first.Scalar();
    if (std::find(visited_.begin(), visited_.end(), k) != visited_.end()) continue;
    if (accept_other_) {
      out_[k] = YAML::Clone(it->second);
      continue;
    }
    std::vector<std::string> allowed = visited_;
    std::sort(allowed.begin(), allowed.end());
    allowed.erase(std::unique(allowed.begin(), allowed.end()), allowed.end());
    if (k == "<<") {  // yaml-cpp reads a merge key as a plain key
      problem_at(it->first, key_path(k),
                 "YAML merge keys ('<<: *anchor') are not supported here: write the keys out (an anchor "
                 "with '*alias' as a whole value works)");
      continue;
    }
    std::string msg = fmt::format("unknown key '{}'", k);
    const std::string near = closest(k, allowed);
    if (!near.empty()) msg += fmt::format("; did you mean '{}'?", near);
    // A misspelt required key or section: the "did you mean" says it all, not
    // also "missing".
    auto& list = shared_->problems;
    if (!near.empty())
      std::erase_if(list, [&](const Problem& p) {
        return p.path == key_path(near) &&
               (is_missing_key(p.message) || p.message.starts_with("missing required section;"));
      });
    if (allowed.empty())
      msg += " (this section takes no keys)";
    else
      msg += fmt::format(" (allowed here: {})", fmt::join(allowed, ", "));
    problem_at(it->first, key_path(k), msg);
  }
}

// -------------------------------------------------------------- Describer --

void Describer::value(const Key& key, ValueRef ref) {
  KeyDoc d;
  d.path = path_.empty() ? std::string(key.name) : path_ + "." + std::string(key.name);
  d.type = std::visit(TypeName{}, ref);
  d.default_value = key.required ? "(required)" : to_text(ref);
  d.rule = key.rule.text;
  d.doc = std::string(key.doc);
  d.required = key.required;
  rows_->push_back(std::move(d));
}

void Describer::section(std::string_view name, std::string_view doc,
                        const std::function<void(Visitor&)>& body, bool* present) {
  if (present) *present = false;
  const std::string p = path_.empty() ? std::string(name) : path_ + "." + std::string(name);
  rows_->push_back(KeyDoc{p, "section", "", "", std::string(doc), false});
  Describer sub(p, rows_);
  body(sub);
}

void Describer::entries(std::string_view name, std::string_view doc,
                        const std::function<void(const std::string&, Visitor&)>& body,
                        const std::vector<std::string>& allowed) {
  const std::string p = path_.empty() ? std::string(name) : path_ + "." + std::string(name);
  const std::string names = allowed.empty() ? std::string("<name>") : fmt::format("<{}>", fmt::join(allowed, "|"));
  rows_->push_back(KeyDoc{p, "mapping", "", allowed.empty() ? "" : "names: " + fmt::format("{}", fmt::join(allowed, ", ")),
                          std::string(doc), false});
  Describer sub(p + "." + names, rows_);
  body(allowed.empty() ? std::string("name") : allowed.front(), sub);
}

void Describer::list(std::string_view name, std::string_view doc,
                     const std::function<void(Visitor&)>& body) {
  const std::string p = path_.empty() ? std::string(name) : path_ + "." + std::string(name);
  rows_->push_back(KeyDoc{p, "list", "[]", "", std::string(doc), false});
  Describer sub(p + "[]", rows_);
  body(sub);
}

void Describer::choices(std::string_view name, std::string_view doc,
                        const std::vector<Alternative>& alternatives) {
  const std::string p = path_.empty() ? std::string(name) : path_ + "." + std::string(name);
  std::vector<std::string> names;
  for (const auto& a : alternatives) names.push_back(a.name);
  rows_->push_back(KeyDoc{p, "list", "[]", "items: " + fmt::format("{}", fmt::join(names, ", ")),
                          std::string(doc), false});
  for (const auto& a : alternatives) {
    rows_->push_back(KeyDoc{p + "[]." + a.name, "item", "", "", a.doc, false});
    Describer sub(p + "[]." + a.name, rows_);
    a.body(sub);
  }
}

// -------------------------------------------------------------- load/set --

std::string file_problem(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    return ec.message();  // e.g. a folder on the way unreadable
  if (!fs::exists(st)) return "no such file";
  if (fs::is_directory(st)) return "is a directory, not a file";
  if (fs::is_fifo(st)) return "";  // a pipe (<(...)): opening it here would take its writer's data
  if (!fs::is_regular_file(st)) return "is not a regular file";
  if (!std::ifstream(path)) return "cannot be read (check its permissions)";
  return "";
}

namespace {

// A YAML syntax error in words a newcomer can act on, where the parser's own
// ("end of sequence flow not found", "illegal map value") names only where it
// gave up: a tab in the indentation of a line up to that point, a bracket or
// brace opened before it and never closed, or the indentation.
Problem syntax_problem(const std::string& path, const std::string& text, const YAML::ParserException& e) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  const std::size_t last = std::min<std::size_t>(lines.size(), static_cast<std::size_t>(e.mark.line) + 1);
  for (std::size_t i = 0; i < last; ++i) {  // tabs first: they confuse every other reading
    const std::size_t content = lines[i].find_first_not_of(" \t");
    if (content == std::string::npos || lines[i][content] == '#') continue;  // blank or comment: tabs allowed
    if (const std::size_t tab = lines[i].find('\t'); tab < content)
      return {path, int(i) + 1, int(tab) + 1, "",
              "YAML syntax error: a tab in the indentation; YAML indents with spaces only"};
  }
  if (e.msg.find("flow not found") != std::string::npos) {
    struct Open {
      char c;
      int line, column;
    };
    std::vector<Open> open;  // brackets still open, outside quotes and comments
    for (std::size_t i = 0; i < last; ++i) {
      char quote = 0;
      for (std::size_t c = 0; c < lines[i].size(); ++c) {
        const char ch = lines[i][c];
        if (quote) {
          if (ch == quote) quote = 0;
        } else if (ch == '\'' || ch == '"') {
          quote = ch;
        } else if (ch == '#' && (c == 0 || lines[i][c - 1] == ' ')) {
          break;
        } else if (ch == '[' || ch == '{') {
          open.push_back({ch, int(i) + 1, int(c) + 1});
        } else if ((ch == ']' || ch == '}') && !open.empty()) {
          open.pop_back();
        }
      }
    }
    if (!open.empty())
      return {path, open.front().line, open.front().column, "",
              fmt::format("YAML syntax error: this '{}' is never closed; close it with '{}'", open.front().c,
                          open.front().c == '[' ? ']' : '}')};
  }
  std::string msg = "YAML syntax error: " + e.msg;
  if (e.msg.find("map") != std::string::npos)
    msg +=
        " (check the indentation: the keys of one section start in the same column, and a key's value "
        "follows ': ')";
  return {path, e.mark.line + 1, e.mark.column + 1, "", msg};
}

}  // namespace

YAML::Node load_yaml_file(const std::string& path) {
  if (const std::string why = file_problem(path); !why.empty())
    throw ConfigError(
        {Problem{path, 0, 0, "", why == "no such file" ? "cannot open the file (does it exist?)" : why}});
  std::ifstream file(path);
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::istringstream in(text);
  try {
    YAML::Node n = YAML::Load(in);
    if (!n || n.IsNull()) throw ConfigError({Problem{path, 1, 1, "", "the file is empty"}});
    if (!n.IsMap())
      throw ConfigError({Problem{path, n.Mark().line + 1, n.Mark().column + 1, "",
                                 "the top level must be a mapping (run:, domain:, fluid:, ...)"}});
    return n;
  } catch (const YAML::ParserException& e) {
    throw ConfigError({syntax_problem(path, text, e)});
  }
}

void apply_override(YAML::Node& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ConfigError({Problem{"--set", 0, 0, assignment, "expected key.path=value"}});
  const std::string path = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::ParserException& e) {
    throw ConfigError({Problem{"--set", 0, 0, path, "cannot parse the value: " + e.msg}});
  }
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string p; std::getline(ss, p, '.');) {
    if (p.empty()) throw ConfigError({Problem{"--set", 0, 0, path, "empty key in the path"}});
    parts.push_back(p);
  }
  // yaml-cpp nodes are references: walk down, creating maps where missing.
  std::vector<YAML::Node> chain{root};
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    YAML::Node next = chain.back()[parts[i]];
    if (next.IsDefined() && !next.IsNull() && !next.IsMap())
      throw ConfigError({Problem{"--set", 0, 0, path, "'" + parts[i] + "' is not a section"}});
    if (!next.IsDefined() || next.IsNull()) {
      chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
      next = chain.back()[parts[i]];
    }
    chain.push_back(next);
  }
  chain.back()[parts.back()] = value;
}

}  // namespace coflow::config
