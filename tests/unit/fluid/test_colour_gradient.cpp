// The colour-gradient model's relaxation time across the interface
// (fluid/lbm/colour_gradient.hpp): the harmonic mean of the two viscosities
// (Leclaire et al. 2017 eq. 13), with the colour fraction held to [-1, 1].
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "fluid/lbm/colour_gradient.hpp"
#include "fluid/lbm/phase_series.hpp"
#include "tests/unit/worst.hpp"

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

// One fluid with interior solids runs on the two-phase core with blue +0 and
// no surface tension; its kernels then call red_collide_lanes instead of
// colour_collide_lanes, which must give the same red bits and leave blue +0
// whatever the colour gradient (two_phase_core.cpp relies on it to skip the
// colour field). Populations near equilibrium with a flow, both lattices,
// both formulations, BGK and TRT, per cell and per lane.
namespace {
template <class L, bool Incompressible>
void check_red_alone(bool trt) {
  using namespace coflow::fluid::lbm;
  const ColourParams p{0.0, 0.7, 0.8, 0.8, trt, 0.1875};
  const double F[3] = {1e-5, -2e-6, 3e-6};
  double worst = 0.0;
  int compared = 0;
  const auto population = [](int cell, int q) {
    const double eu = 0.05 * L::e[q][0] - 0.03 * L::e[q][1] + 0.02 * L::e[q][2];
    return L::w[q] * (1.0 + 0.01 * std::sin(1.7 * cell + q) + 3.0 * eu);
  };
  for (int cell = 0; cell < 64; ++cell) {
    double r[L::Q], b[L::Q], red[L::Q];
    for (int q = 0; q < L::Q; ++q) r[q] = red[q] = population(cell, q), b[q] = 0.0;
    const double g[3] = {0.3 * std::cos(cell), -0.2 + 0.01 * cell, 0.1 * std::sin(2.0 * cell)};
    const double uu = colour_collide<L, Incompressible>(r, b, g, p, F);
    const double uu_red = red_collide_lanes<L, Incompressible, double>(red, p, F);
    CHECK(uu_red == uu);
    for (int q = 0; q < L::Q; ++q) {
      worst = coflow::test::worst_of(worst, std::abs(red[q] - r[q]));
      compared += red[q] == r[q] && b[q] == 0.0 && !std::signbit(b[q]);
    }
    // The same on four lanes.
    Vec4 rl[L::Q];
    for (int q = 0; q < L::Q; ++q) rl[q] = splat<Vec4>(population(cell, q));
    red_collide_lanes<L, Incompressible, Vec4>(rl, p, F);
    for (int q = 0; q < L::Q; ++q) compared += rl[q][2] == r[q];
  }
  INFO("largest difference " << worst);
  CHECK(compared == 64 * 2 * L::Q);  // every red population, blue +0, and the lanes
}
}  // namespace

TEST_CASE("colour gradient: one fluid's collision equals the two-colour one with no blue, bit for bit",
          "[lbm]") {
  using namespace coflow::fluid::lbm;
  for (const bool trt : {false, true}) {
    check_red_alone<D2Q9, true>(trt);
    check_red_alone<D2Q9, false>(trt);
    check_red_alone<D3Q19, true>(trt);
    check_red_alone<D3Q19, false>(trt);
  }
}
