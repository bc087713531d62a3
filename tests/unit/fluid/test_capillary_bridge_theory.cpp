// The reference of the capillary-bridge test (tests/validation/two_phase/
// capillary_bridge.hpp): the exact bridge between touching spheres tends to
// the small-bridge limit 2 pi R gamma cos(theta) (Willett et al. 2000) and
// agrees with the toroidal approximation (Lian et al. 1993) where both hold.
#include <catch2/catch.hpp>

#include "../../validation/two_phase/capillary_bridge.hpp"

namespace {

using coflow::check::capillary_bridge;
using coflow::check::toroidal_force;
using coflow::check::bridge_detail::at_filling;
constexpr double pi = std::numbers::pi, R = 12.0;

double degrees(double d) {
  return d * pi / 180.0;
}

}  // namespace

TEST_CASE("capillary bridge theory: the small-bridge limit", "[check]") {
  for (double theta : {0.0, 30.0, 45.0, 60.0}) {
    const double limit = 2.0 * pi * R * std::cos(degrees(theta));
    // F / limit falls linearly with the filling angle near 0: extrapolated
    // from 0.5 and 1 degree to 0 it is 1.
    const double f1 = at_filling(R, degrees(theta), degrees(0.5)).force / limit;
    const double f2 = at_filling(R, degrees(theta), degrees(1.0)).force / limit;
    CHECK(std::abs(2.0 * f1 - f2 - 1.0) < 2e-3);  // 1e-6 to 2e-4 measured
    CHECK(f1 < 1.0);
  }
}

TEST_CASE("capillary bridge theory: the toroidal approximation and the volume", "[check]") {
  const double theta = degrees(45.0);
  for (double phi : {5.0, 10.0, 20.0, 30.0, 40.0}) {
    const auto b = at_filling(R, theta, degrees(phi));
    // Lian et al. 1993: the toroidal force within a few per cent for such
    // bridges (0.5 to 1.2 % measured).
    CHECK(std::abs(toroidal_force(R, theta, degrees(phi)) / b.force - 1.0) < 0.02);
    // The volume solve gives back the filling angle.
    CHECK(capillary_bridge(R, theta, b.volume).filling == Approx(degrees(phi)).epsilon(1e-9));
  }
  // At theta + phi = 90 degrees the meridian is straight: the bridge is a
  // cylinder of radius R sin(phi) (H = 1 / r_n), its volume the cylinder's
  // less the two spheres' caps.
  const double phi = degrees(45.0);
  const auto b = at_filling(R, theta, phi);
  const double xc = R * (1.0 - std::cos(phi)), rn = R * std::sin(phi);
  CHECK(b.neck == Approx(rn).epsilon(1e-6));
  CHECK(b.volume == Approx(2.0 * (pi * rn * rn * xc - pi * xc * xc * (3.0 * R - xc) / 3.0)).epsilon(1e-6));
  CHECK(b.force == Approx(pi * rn).epsilon(1e-6));  // F = 2 pi r_n - pi r_n^2 / r_n (H = 1/r_n)
}
