#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "fluid/lbm/kernels.hpp"

using namespace coflow::fluid::lbm;

namespace {

// The lean BGK chunk kernel (no force) against the general TRT/Guo chunk
// kernel with tau_minus = tau and F = 0, and against the one-cell kernel, on
// populations perturbed around an equilibrium with |u| ~ 0.05.
template <class L, bool Incompressible>
void lean_matches_general(double tau) {
  constexpr int W = 8;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double lean[L::Q][W], general[L::Q][W], one[W][L::Q];
  for (int w = 0; w < W; ++w) {
    const double u[3] = {0.05 * unit(rng), 0.05 * unit(rng), L::D == 3 ? 0.05 * unit(rng) : 0.0};
    const double rho = 1.0 + 0.02 * unit(rng);
    for (int q = 0; q < L::Q; ++q) {
      const double f = equilibrium<L, Incompressible>(q, rho, u) * (1.0 + 0.01 * unit(rng));
      lean[q][w] = general[q][w] = one[w][q] = f;
    }
  }
  const CollisionParams p = collision_params(tau);
  const double F[3] = {0.0, 0.0, 0.0};
  double u2_lean[W], u2_general[W];
  bgk_chunk<L, Incompressible, W>(lean, p.omega, u2_lean);
  collide_chunk<L, Incompressible, W>(general, p, F, u2_general);
  for (int w = 0; w < W; ++w) {
    const double u2_one = collide<L, Incompressible>(one[w], p, F);
    CHECK(u2_lean[w] == Approx(u2_general[w]).epsilon(1e-14));
    CHECK(u2_lean[w] == Approx(u2_one).epsilon(1e-14));
    for (int q = 0; q < L::Q; ++q) {
      // round-off of a few operations on O(0.1) numbers
      CHECK(std::abs(lean[q][w] - general[q][w]) < 1e-15);
      CHECK(std::abs(lean[q][w] - one[w][q]) < 1e-15);
    }
  }
}

// The vector TRT/Guo kernel (four cells at a time) against the one-cell kernel,
// with a force and tau_minus from the magic parameter.
template <class L, bool Incompressible>
void general_matches_one_cell(double tau, bool trt) {
  constexpr int W = 8;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double chunk[L::Q][W], one[W][L::Q];
  for (int w = 0; w < W; ++w) {
    const double u[3] = {0.05 * unit(rng), 0.05 * unit(rng), L::D == 3 ? 0.05 * unit(rng) : 0.0};
    const double rho = 1.0 + 0.02 * unit(rng);
    for (int q = 0; q < L::Q; ++q)
      chunk[q][w] = one[w][q] = equilibrium<L, Incompressible>(q, rho, u) * (1.0 + 0.01 * unit(rng));
  }
  const CollisionParams p = collision_params(tau, trt, 0.1875);
  const double F[3] = {1e-3 * unit(rng), 1e-3 * unit(rng), L::D == 3 ? 1e-3 * unit(rng) : 0.0};
  double u2[W];
  collide_chunk<L, Incompressible, W>(chunk, p, F, u2);
  for (int w = 0; w < W; ++w) {
    const double u2_one = collide<L, Incompressible>(one[w], p, F);
    CHECK(u2[w] == Approx(u2_one).epsilon(1e-14));
    for (int q = 0; q < L::Q; ++q) CHECK(std::abs(chunk[q][w] - one[w][q]) < 1e-15);
  }
}

}  // namespace

TEST_CASE("vector TRT/Guo kernel equals the one-cell collision", "[lbm]") {
  general_matches_one_cell<D3Q19, false>(0.8, true);
  general_matches_one_cell<D3Q19, true>(0.6, true);
  general_matches_one_cell<D3Q19, false>(0.9, false);
  general_matches_one_cell<D2Q9, false>(0.55, true);
  general_matches_one_cell<D2Q9, true>(1.7, false);
}

TEST_CASE("lean BGK kernel equals the general collision without force", "[lbm]") {
  lean_matches_general<D3Q19, false>(0.8);
  lean_matches_general<D3Q19, true>(0.8);
  lean_matches_general<D2Q9, false>(0.55);
  lean_matches_general<D2Q9, true>(1.7);
}
