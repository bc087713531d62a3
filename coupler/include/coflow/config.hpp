// Strict, self-describing configuration.
//
// Every parameter struct declares its keys once, in a `visit(Visitor&)` function.
// The same declaration is walked by two visitors:
//  - `Reader` reads a YAML mapping, checks types and ranges, rejects unknown and
//    duplicate keys, and records the resolved value (defaults filled in);
//  - `Describer` lists every key with its type, default, rule and doc, for
//    `coflow variants` and docs/config.md.
// So the documentation cannot drift from the parser.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace coflow::config {

using Vec3 = std::array<double, 3>;
using Int3 = std::array<int, 3>;
using Bool3 = std::array<bool, 3>;
using StringList = std::vector<std::string>;

// A number, or the word `auto` (e.g. coupling.window, particles.time_step).
struct AutoDouble {
  bool is_auto = true;
  double value = 0.0;
};

// `auto`, or an explicit block count per axis (e.g. fluid.decomposition).
struct AutoInt3 {
  bool is_auto = true;
  Int3 value{1, 1, 1};
};

// A scalar or a list of numbers (boundary values: a pressure or a velocity).
struct Numbers {
  std::vector<double> values;
};

// A size: a fixed number, or {lognormal: {mean, std}}, or {uniform: {min, max}}.
struct Distribution {
  enum class Kind { fixed, uniform, lognormal };
  Kind kind = Kind::fixed;
  double a = 0.0;  // fixed value | uniform min | lognormal mean
  double b = 0.0;  // uniform max | lognormal standard deviation
  double mean() const;
};

// A file name; a relative one is taken relative to the configuration file, and
// the resolved configuration records it absolute.
struct FilePath {
  std::string path;
  bool empty() const { return path.empty(); }
};

using ValueRef = std::variant<double*, int*, std::uint64_t*, bool*, std::string*, Vec3*, Int3*,
                              Bool3*, StringList*, AutoDouble*, AutoInt3*, Numbers*, Distribution*, FilePath*>;

// A rule on a value: a description for the docs, and a test returning an error
// message (empty when the value is fine).
struct Rule {
  std::string text;
  std::function<std::string(const ValueRef&)> test;
};

Rule greater(double bound);
Rule at_least(double bound);
Rule in_range(double lo, double hi);  // closed interval
Rule below(double bound);
Rule positive();          // > 0, for numbers and for every entry of vectors
Rule non_negative();      // >= 0, likewise
Rule one_of(std::vector<std::string> names);
Rule each_one_of(std::vector<std::string> names);  // for string lists, each entry once

struct Key {
  std::string_view name;
  std::string_view doc;
  bool required = false;
  Rule rule{};
};

// One alternative of a list of one-key items, e.g. `initial: [{random: {...}}]`.
struct Alternative {
  std::string name;
  std::string doc;
  std::function<void(class Visitor&)> body;
};

class Visitor {
 public:
  virtual ~Visitor() = default;

  virtual void value(const Key& key, ValueRef ref) = 0;

  // A nested mapping. `present` (optional) reports whether the user wrote it.
  virtual void section(std::string_view name, std::string_view doc,
                       const std::function<void(Visitor&)>& body, bool* present = nullptr) = 0;

  // A mapping from user-chosen names to sections (species, boundaries).
  // `allowed` (optional) restricts the names.
  virtual void entries(std::string_view name, std::string_view doc,
                       const std::function<void(const std::string&, Visitor&)>& body,
                       const std::vector<std::string>& allowed = {}) = 0;

  // A list of sections of one shape.
  virtual void list(std::string_view name, std::string_view doc,
                    const std::function<void(Visitor&)>& body) = 0;

  // A list whose items are one-key mappings naming an alternative.
  virtual void choices(std::string_view name, std::string_view doc,
                       const std::vector<Alternative>& alternatives) = 0;

  // Report an inconsistency found by a check that spans several keys. `key` is
  // the key (in the current section) the message is attached to.
  virtual void fail(std::string_view key, const std::string& message) = 0;

  // Keep keys no declaration reads (for `external` variants, whose own
  // executable checks them).
  virtual void accept_other_keys() {}

  // The directory of the file being read ("" while describing): relative file
  // names in a configuration are relative to it.
  virtual std::string base_dir() const { return ""; }

  // Problems found so far (0 while describing), and a switch that keeps the
  // checks spanning several keys (fail()) quiet from now on: after a broken
  // domain they would only repeat it in other words.
  virtual std::size_t problem_count() const { return 0; }
  // Whether a problem found since the count `since` sits at one of `paths`.
  virtual bool problems_since(std::size_t, const std::vector<std::string>&) const { return false; }
  virtual void quiet_cross_checks() {}

  // True while reading a user's file; false while describing.
  virtual bool reading() const = 0;
  // Whether the user wrote this key in the current section.
  virtual bool given(std::string_view key) const = 0;

  template <class T>
  void operator()(std::string_view name, T& v, std::string_view doc, Rule rule = {}) {
    value(Key{name, doc, false, std::move(rule)}, ValueRef(&v));
  }
  template <class T>
  void required(std::string_view name, T& v, std::string_view doc, Rule rule = {}) {
    value(Key{name, doc, true, std::move(rule)}, ValueRef(&v));
  }
};

// One error in a configuration, with where it is.
struct Problem {
  std::string file;
  int line = 0;    // 1-based; 0 when unknown
  int column = 0;  // 1-based
  std::string path;
  std::string message;
  std::string format() const;  // "file:line:col: path: message"
};

class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(std::vector<Problem> problems);
  const std::vector<Problem>& problems() const { return problems_; }

 private:
  std::vector<Problem> problems_;
};

// Reads a YAML mapping strictly. Problems are collected, not thrown one by one,
// so that a user sees every mistake in one go; `Reader::check()` throws them.
class Reader final : public Visitor {
 public:
  Reader(YAML::Node node, std::string file, std::string path = "");
  ~Reader() override;

  void value(const Key& key, ValueRef ref) override;
  void section(std::string_view name, std::string_view doc,
               const std::function<void(Visitor&)>& body, bool* present) override;
  void entries(std::string_view name, std::string_view doc,
               const std::function<void(const std::string&, Visitor&)>& body,
               const std::vector<std::string>& allowed) override;
  void list(std::string_view name, std::string_view doc,
            const std::function<void(Visitor&)>& body) override;
  void choices(std::string_view name, std::string_view doc,
               const std::vector<Alternative>& alternatives) override;
  void fail(std::string_view key, const std::string& message) override;
  bool reading() const override { return true; }
  std::size_t problem_count() const override;
  bool problems_since(std::size_t since, const std::vector<std::string>& paths) const override;
  void quiet_cross_checks() override;
  bool given(std::string_view key) const override;
  void accept_other_keys() override;
  std::string base_dir() const override;

  // Reject keys that no declaration read, with a "did you mean" hint. Called by
  // `section` etc. for nested mappings; call it once for the top level.
  void finish();
  // Throw a ConfigError if any problem was found.
  void check() const;
  const std::vector<Problem>& problems() const;
  // The resolved configuration: every declared key with its value or default.
  YAML::Node resolved() const;

 private:
  struct Shared;
  Reader(YAML::Node node, std::shared_ptr<Shared> shared, std::string path, YAML::Node out);
  Reader child(YAML::Node node, std::string_view name, YAML::Node out) const;
  std::string key_path(std::string_view key) const;
  void problem_at(const YAML::Node& where, const std::string& path, const std::string& msg);
  void check_duplicates();
  void collapse_missing(std::size_t first, const std::string& path);

  YAML::Node node_;
  YAML::Node anchor_;  // nearest written ancestor, for positions of absent sections
  std::shared_ptr<Shared> shared_;
  std::string path_;
  YAML::Node out_;
  std::vector<std::string> visited_;
  bool finished_ = false;
  bool accept_other_ = false;
};

// One row of the documentation.
struct KeyDoc {
  std::string path;
  std::string type;
  std::string default_value;
  std::string rule;
  std::string doc;
  bool required = false;
};

class Describer final : public Visitor {
 public:
  explicit Describer(std::string path = "") : path_(std::move(path)) {}
  void value(const Key& key, ValueRef ref) override;
  void section(std::string_view name, std::string_view doc,
               const std::function<void(Visitor&)>& body, bool* present) override;
  void entries(std::string_view name, std::string_view doc,
               const std::function<void(const std::string&, Visitor&)>& body,
               const std::vector<std::string>& allowed) override;
  void list(std::string_view name, std::string_view doc,
            const std::function<void(Visitor&)>& body) override;
  void choices(std::string_view name, std::string_view doc,
               const std::vector<Alternative>& alternatives) override;
  void fail(std::string_view, const std::string&) override {}
  bool reading() const override { return false; }
  bool given(std::string_view) const override { return false; }

  const std::vector<KeyDoc>& rows() const { return *rows_; }

 private:
  Describer(std::string path, std::shared_ptr<std::vector<KeyDoc>> rows)
      : path_(std::move(path)), rows_(std::move(rows)) {}
  std::string path_;
  std::shared_ptr<std::vector<KeyDoc>> rows_ = std::make_shared<std::vector<KeyDoc>>();
};

// Closest candidate by edit distance, or "" when nothing is close.
std::string closest(std::string_view word, const std::vector<std::string>& candidates);

// What keeps a named input file from being read, "" when nothing does: "no
// such file", "is a directory, not a file", "is not a regular file", "cannot
// be read (check its permissions)" or the system's reason (a pipe reads).
std::string file_problem(const std::string& path);

// Load a YAML file; syntax errors become ConfigError with the file position.
YAML::Node load_yaml_file(const std::string& path);

// Apply `key.path=value` overrides (from `coflow run --set`). The value is parsed
// as YAML (so `--set fluid.lbm.tau=0.9`, `--set domain.cells=[8,8,1]`).
void apply_override(YAML::Node& root, const std::string& assignment);

// Text of a value for the docs and messages.
std::string to_text(const ValueRef& ref);

}  // namespace coflow::config
