// The colour-gradient model's relaxation time across the interface
// (fluid/lbm/colour_gradient.hpp): the harmonic mean of the two viscosities
// (Leclaire et al. 2017 eq. 13), with the colour fraction held to [-1, 1].
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "fluid/lbm/colour_gradient.hpp"
#include "fluid/lbm/phase_series.hpp"

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

// The phase columns of series/fluid.csv count the pore volume (1 - eps) dV of
// a psm grain's cells: a red grain's inside is no red pore space. Before
// 2026-12-05 a cell wholly covered by a grain counted as a whole cell of pore
// space (found by review): here 1/4 of the pore space would have read red.
TEST_CASE("phase series: a grain's cells count by their pore volume", "[lbm]") {
  const coflow::fluid::lbm::Units units;  // lattice units: dx = dt = rho = 1
  // Four cells in a row: blue fluid, blue fluid, a cell wholly inside a red
  // grain, a cell half covered (red in its pores), all at rest but the last.
  const std::vector<double> rho{1, 1, 1, 1}, phase{-1, -1, 1, 1}, solid{0, 0, 0, 0}, grain{0, 0, 1, 0.5};
  const std::vector<double> u{0, 0, 0, 0, 0, 0, 0, 0, 0, 0.2, 0, 0};
  const auto v =
      coflow::fluid::lbm::phase_values(units, {4, 1, 1}, rho, u, phase, solid, grain, MPI_COMM_SELF);
  CHECK(v[0] == 2.0);                              // red mass: every population counts
  CHECK(std::abs(v[2] - 0.5 / 2.5) <= 1e-15);      // saturation: 0.5 of 2.5 cells of pore volume
  CHECK(std::abs(v[3] - 0.2 * 0.5 / 4) <= 1e-15);  // red flux: u psi (1 - eps), over the 4 cells' length
  // Without grains every cell is pore space.
  const auto none =
      coflow::fluid::lbm::phase_values(units, {4, 1, 1}, rho, u, phase, solid, {}, MPI_COMM_SELF);
  CHECK(none[2] == 0.5);
}
