#include "fluid/profile_expression.hpp"

#include <fmt/format.h>
#include <muParser.h>

#include <cmath>
#include <numbers>
#include <regex>
#include <stdexcept>

namespace coflow::fluid {

struct ProfileExpression::State {
  mu::Parser parser;
  std::string text;
  double x = 0, y = 0, z = 0, t = 0;
  bool uses_time = false;
};

ProfileExpression::ProfileExpression(const std::string& text) : state_(std::make_shared<State>()) {
  State& s = *state_;
  s.text = text;
  try {
    s.parser.DefineVar("x", &s.x);
    s.parser.DefineVar("y", &s.y);
    s.parser.DefineVar("z", &s.z);
    s.parser.DefineVar("t", &s.t);
    s.parser.DefineConst("pi", std::numbers::pi);
    s.parser.DefineConst("e", std::numbers::e);
    s.parser.SetExpr(text);
    s.parser.Eval();  // parses: a syntax error or an unknown name throws here
    s.uses_time = s.parser.GetUsedVar().count("t") > 0;
  } catch (const mu::Parser::exception_type& e) {
    // muParser counts from 0 and says so in some messages ("... found at
    // position 2."): drop its count, give ours from 1.
    const std::string msg =
        std::regex_replace(e.GetMsg(), std::regex(R"(\s*(found )?at position \d+\.?$)"), "");
    const int pos = e.GetPos();
    const std::string at = pos < 0 ? ""
                           : static_cast<std::size_t>(pos) >= text.size()
                               ? " at the end"
                               : fmt::format(" at character {}", pos + 1);
    throw std::runtime_error(
        fmt::format("cannot read the expression `{}`: {}{}; it may use x, y, z (m), t (s), pi, "
                    "e and functions such as sin, exp, sqrt, min",
                    text, msg, at));
  }
}

bool ProfileExpression::uses_time() const {
  return state_ && state_->uses_time;
}

double ProfileExpression::operator()(const double x[3], double t) const {
  State& s = *state_;
  s.x = x[0], s.y = x[1], s.z = x[2], s.t = t;
  const double f = s.parser.Eval();
  if (!std::isfinite(f))
    throw std::runtime_error(
        fmt::format("the profile expression `{}` gives {} at x = ({}, {}, {}) m, t = {} s", s.text, f, x[0],
                    x[1], x[2], t));
  return f;
}

}  // namespace coflow::fluid
