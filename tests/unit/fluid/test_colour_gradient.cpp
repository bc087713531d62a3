// The colour-gradient model's relaxation time across the interface
// (fluid/lbm/colour_gradient.hpp): the harmonic mean of the two viscosities
// (Leclaire et al. 2017 eq. 13), with the colour fraction held to [-1, 1].
#include <catch2/catch.hpp>
#include <cmath>

#include "fluid/lbm/colour_gradient.hpp"

using coflow::fluid::lbm::mixed_tau;
using coflow::fluid::lbm::Vec4;

TEST_CASE("colour gradient: the mixed relaxation time stays between the fluids'", "[lbm]") {
  // A viscosity ratio of 100: nu_b / nu_r = (tau_b - 1/2) / (tau_r - 1/2).
  const double tau_r = 0.51, tau_b = 1.5;
  CHECK(std::abs(mixed_tau(1.0, tau_r, tau_b) - tau_r) <= 1e-15);
  CHECK(std::abs(mixed_tau(-1.0, tau_r, tau_b) - tau_b) <= 1e-15);
  // psi = 0: 1 / nu = (1 / nu_r + 1 / nu_b) / 2.
  const double nu = 2.0 / (1.0 / (tau_r - 0.5) + 1.0 / (tau_b - 0.5));
  CHECK(std::abs(mixed_tau(0.0, tau_r, tau_b) - (0.5 + nu)) <= 1e-15);
  // A red density below zero: psi = -1.03 is past -1 - 2 / (M - 1) = -1.0202,
  // where the unclamped mean's denominator changes sign (tau below 1/2).
  for (double psi : {-1.03, -1.5, 1.2}) {
    const double t = mixed_tau(psi, tau_r, tau_b);
    INFO("psi " << psi << ": tau " << t);
    CHECK(t == mixed_tau(psi < 0 ? -1.0 : 1.0, tau_r, tau_b));
    const Vec4 lanes = mixed_tau(Vec4{psi, 0.0, -1.0, 1.0}, tau_r, tau_b);
    CHECK(lanes[0] == t);
    CHECK(lanes[1] == mixed_tau(0.0, tau_r, tau_b));
  }
}
