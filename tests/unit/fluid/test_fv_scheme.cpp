// fv's IMEX coefficients (fluid/fv/scheme.hpp) against the polynomials they
// must reproduce exactly, at variable steps (omega = dt / dt_prev).
#include <catch2/catch.hpp>
#include <cmath>

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
