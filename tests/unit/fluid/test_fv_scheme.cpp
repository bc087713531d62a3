// fv's IMEX coefficients (fluid/fv/scheme.hpp) against the polynomials they
// must reproduce exactly, at variable steps (omega = dt / dt_prev).
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "fluid/fv/scheme.hpp"

using coflow::fluid::fv::Imex;

TEST_CASE("fv IMEX: the extrapolation to the new time is exact for a linear function", "[fv]") {
  // u(t) = 3 + 2 t at t^{n-1} = -dt_prev, t^n = 0, t^{n+1} = dt.
  for (double omega : {0.5, 1.0, 1.7}) {
    const double dt = 0.1, dt_prev = dt / omega;
    const double un = 3.0, un_1 = 3.0 - 2.0 * dt_prev, exact = 3.0 + 2.0 * dt;
    for (const Imex& s : {Imex::sbdf2(omega), Imex::cnab2(omega)}) {
      INFO("omega " << omega << ", theta " << s.theta);
      CHECK(std::abs(s.e0 * un + s.e1 * un_1 - exact) <= 1e-14);
    }
    // Adams-Bashforth's weights (cnab2's b0, b1) reach the step's middle.
    const Imex c = Imex::cnab2(omega);
    CHECK(std::abs(c.b0 * un + c.b1 * un_1 - (3.0 + dt)) <= 1e-14);
  }
  const Imex f = Imex::first();
  CHECK(f.e0 == 1.0);
  CHECK(f.e1 == 0.0);
}

TEST_CASE("fv step_window: checks the window's last step, refuses a step that collapses", "[fv]") {
  double time = 0.0, last = 0.0;
  int checks = 0, steps = 0;
  const auto step = [&](double dt, double t) {
    time = t, last = dt;
    ++steps;
  };
  SECTION("the velocity is checked after the last step (limit() throws there on a value not finite)") {
    bool broken = false;
    const auto limit = [&] {
      ++checks;
      if (broken) throw std::runtime_error("not finite");
      return 0.25;
    };
    CHECK_THROWS_WITH(coflow::fluid::fv::step_window(time, last, 1.0, limit,
                                                     [&](double dt, double t) {
                                                       step(dt, t);
                                                       broken = steps == 4;  // the last step goes wrong
                                                     }),
                      "not finite");
    // Before 2026-12-05 the loop stopped after the fourth step without a
    // check: the NaN went on to the window's output and checkpoint.
    CHECK(steps == 4);
    CHECK(broken);
    CHECK(checks == 5);
  }
  SECTION("a step too small for the window is an error, not one sliver of a step") {
    // (end - time) / dt = 1e21 is beyond a long: lround gave LONG_MIN, so one
    // step of 2e-21 s ended the window at t = 1.
    CHECK_THROWS_WITH(coflow::fluid::fv::step_window(
                          time, last, 1.0, [] { return 1e-21; }, step),
                      Catch::Contains("blowing up"));
    CHECK(steps == 0);
  }
}
