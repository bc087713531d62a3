// A velocity face's profile as a formula (fluid/profile_expression.hpp,
// profile: expression): values against the same formulas in C++, the time
// variable seen, copies independent of the original's lifetime, and bad
// formulas refused with the place at fault.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "fluid/profile_expression.hpp"

using coflow::fluid::ProfileExpression;

TEST_CASE("profile expression: values of x, y, z and t", "[fluid]") {
  const ProfileExpression parabola("4*y*(1-y)");
  const double p[3] = {0.3, 0.25, -2.0};
  CHECK(parabola(p, 0.0) == 4 * 0.25 * (1 - 0.25));
  CHECK_FALSE(parabola.uses_time());
  const ProfileExpression wave("sin(2*pi*t/0.5) * exp(-z) + (x > 0.2 ? 1 : 0) + e");
  CHECK(wave.uses_time());
  for (double t : {0.0, 0.1, 0.37})
    CHECK(wave(p, t) == Approx(std::sin(2 * std::numbers::pi * t / 0.5) * std::exp(2.0) + 1 + std::numbers::e)
                            .epsilon(1e-15));
  CHECK(ProfileExpression("1.5e-3 * min(x, y)")(p, 0.0) == Approx(1.5e-3 * 0.25).epsilon(1e-15));
}

TEST_CASE("profile expression: a copy outlives the original", "[fluid]") {
  ProfileExpression copy;
  CHECK(copy.empty());
  {
    const ProfileExpression original("x + 2*y");
    copy = original;
  }
  const double p[3] = {1.0, 3.0, 0.0};
  CHECK(copy(p, 0.0) == 7.0);
}

TEST_CASE("profile expression: bad formulas say what and where", "[fluid]") {
  CHECK_THROWS_WITH(ProfileExpression("4*y*(1-y"), Catch::Contains("Missing parenthesis at the end"));
  CHECK_THROWS_WITH(ProfileExpression("4*r"), Catch::Contains("Unexpected token \"r\" at character 3"));
  CHECK_THROWS_WITH(ProfileExpression(""), Catch::Contains("cannot read the expression ``"));
  const ProfileExpression inverse("1/y");
  const double zero[3] = {0.0, 0.0, 0.0};
  CHECK_THROWS_WITH(inverse(zero, 2.0), Catch::Contains("gives inf at x = (0, 0, 0) m, t = 2 s"));
}
