// A velocity face's profile given as a formula (profile: expression): the
// factor on the face's value at a point (x, y, z in m) and time t (s).
// muParser (Debian's libmuparser-dev) parses and evaluates it: a kept library
// rather than a home-made parser. Part of the fluid schema library.
#pragma once

#include <memory>
#include <string>

namespace coflow::fluid {

class ProfileExpression {
 public:
  ProfileExpression() = default;
  // Parses `text` (variables x, y, z, t; constants pi and e; muParser's
  // functions: sin, cos, exp, sqrt, abs, min, max, ...); throws
  // std::runtime_error "cannot read the expression ...: what is wrong at
  // character N (or: at the end)" for a syntax error or an unknown name.
  explicit ProfileExpression(const std::string& text);
  bool empty() const { return !state_; }
  bool uses_time() const;  // the formula names t
  // The factor at point x and time t; throws std::runtime_error naming the
  // point when it is not a finite number.
  double operator()(const double x[3], double t) const;

 private:
  struct State;
  std::shared_ptr<State> state_;  // copies share one parser: its variables are addresses into State
};

}  // namespace coflow::fluid
