#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "coflow/memory.hpp"
#include "fluid/lbm/collision.hpp"
#include "fluid/lbm/psm_kernel.hpp"

using namespace coflow::fluid::lbm;

namespace {

// The populations of a 32 x 3 x 3 block perturbed around equilibria with
// |u| ~ 0.05, held twice: packed (stride n) and spaced (stride
// spaced_stride). The line kernels update cells of the middle row, pulling
// from all nine neighbour rows.
template <class L, bool Incompressible>
struct Row {
  static constexpr long nx = 32, n = nx * 3 * 3;  // packed stride
  static constexpr long base = nx * (1 + 3 * (L::D == 3 ? 1 : 0));  // the middle row
  alignas(64) double src[L::Q * n];
  alignas(64) double dst[L::Q * n];
  coflow::StridedArrays<double> spaced_src{L::Q, spaced_stride, n}, spaced_dst{L::Q, spaced_stride, n};
  long off[L::Q];
  explicit Row(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (long c = 0; c < n; ++c) {
      const double u[3] = {0.05 * unit(rng), 0.05 * unit(rng), L::D == 3 ? 0.05 * unit(rng) : 0.0};
      const double rho = 1.0 + 0.02 * unit(rng);
      for (int q = 0; q < L::Q; ++q) {
        src[q * n + c] = equilibrium<L, Incompressible>(q, rho, u) * (1.0 + 0.01 * unit(rng));
        spaced_src[q * spaced_stride + c] = src[q * n + c];
      }
    }
    for (int q = 0; q < L::Q; ++q) off[q] = L::e[q][0] + nx * (L::e[q][1] + 3 * L::e[q][2]);
  }
  LineRef packed() { return LineRef{src + base, dst + base, n, off}; }
  SpacedRef<L> spaced() { return SpacedRef<L>(spaced_src.data(), spaced_dst.data(), base, off); }
  double out(bool spaced, int q, long i) const {
    return spaced ? spaced_dst[q * spaced_stride + base + i] : dst[q * n + base + i];
  }
  // The one-cell kernel on the pulled populations of cell i of the row.
  double one_cell(long i, const CollisionParams& p, const double* F, double* f) const {
    for (int q = 0; q < L::Q; ++q) f[q] = src[q * n + base + i - off[q]];
    return collide<L, Incompressible>(f, p, F);
  }
};

// The eight cells from x written by a line kernel on both layouts equal the
// one-cell kernel's, and lane l of the returned u^2 is the larger of cells
// x + l and x + 4 + l.
template <class L, bool Incompressible>
void check_line(const Row<L, Incompressible>& row, long x, const CollisionParams& p, const double* F,
                const Vec4 (&u2)[2]) {
  constexpr int Q = L::Q;
  double u2_one[8];
  for (long c = x; c < x + 8; ++c) {
    double f[Q];
    u2_one[c - x] = row.one_cell(c, p, F, f);
    for (int spaced = 0; spaced < 2; ++spaced)  // round-off of a few operations on O(0.1) numbers
      for (int q = 0; q < Q; ++q) CHECK(std::abs(row.out(spaced, q, c) - f[q]) < 1e-15);
  }
  for (int spaced = 0; spaced < 2; ++spaced)
    for (int l = 0; l < 4; ++l) {
      const double larger = std::max(u2_one[l], u2_one[l + 4]);
      CHECK(std::abs(u2[spaced][l] - larger) <= 1e-14 * larger);  // u^2 by another path: round-off
    }
}

// The lean BGK line kernel (no force, eight cells) against the one-cell
// kernel, on both layouts, with cached and with streaming stores.
template <class L, bool Incompressible, bool Stream>
void lean_matches_one_cell(double tau) {
  constexpr long x = 8;  // the line's first cell
  std::mt19937_64 rng(7);
  Row<L, Incompressible> row(rng);
  const CollisionParams p = collision_params(tau);
  const double F[3] = {0.0, 0.0, 0.0};
  const Vec4 u2[2] = {bgk_line<L, Incompressible, Stream>(row.packed(), x, p.omega),
                      bgk_line<L, Incompressible, Stream>(row.spaced(), x, p.omega)};
#if defined(__AVX__)
  _mm_sfence();
#endif
  check_line(row, x, p, F, u2);
}

// The general line kernel (TRT, Guo forcing) against the one-cell kernel,
// with a force and tau_minus from the magic parameter, on both layouts.
template <class L, bool Incompressible>
void general_matches_one_cell(double tau, bool trt) {
  constexpr long x = 16;
  std::mt19937_64 rng(11);
  Row<L, Incompressible> row(rng);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const CollisionParams p = collision_params(tau, trt, 0.1875);
  const double F[3] = {1e-3 * unit(rng), 1e-3 * unit(rng), L::D == 3 ? 1e-3 * unit(rng) : 0.0};
  const Vec4 u2[2] = {collide_line<L, Incompressible, false>(row.packed(), x, p, F),
                      collide_line<L, Incompressible, false>(row.spaced(), x, p, F)};
  check_line(row, x, p, F, u2);
}

}  // namespace

TEST_CASE("general line kernel (TRT, Guo) equals the one-cell collision", "[lbm]") {
  general_matches_one_cell<D3Q19, false>(0.8, true);
  general_matches_one_cell<D3Q19, true>(0.6, true);
  general_matches_one_cell<D3Q19, false>(0.9, false);
  general_matches_one_cell<D2Q9, false>(0.55, true);
  general_matches_one_cell<D2Q9, true>(1.7, false);
}

TEST_CASE("lean BGK line kernel equals the one-cell collision without force", "[lbm]") {
  lean_matches_one_cell<D3Q19, false, false>(0.8);
  lean_matches_one_cell<D3Q19, false, true>(0.8);
  lean_matches_one_cell<D3Q19, true, true>(0.8);
  lean_matches_one_cell<D2Q9, false, true>(0.55);
  lean_matches_one_cell<D2Q9, true, false>(1.7);
}

namespace {

// A partially saturated cell with no solid (eps = 0: B = 0) is a fluid cell:
// psm_collide must give collide()'s populations, with BGK and with TRT (the
// odd parts relaxing with omega_minus), a force on, both formulations. A
// fully covered cell (eps = 1: B = 1) takes Omega^s alone, whatever the
// fluid's relaxation.
template <class L, bool Incompressible>
void psm_is_the_fluid_collision_without_solid(double tau, bool trt) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const CollisionParams p = collision_params(tau, trt, 0.1875);
  const double F[3] = {1e-3 * unit(rng), 1e-3 * unit(rng), L::D == 3 ? 1e-3 * unit(rng) : 0.0};
  const double u[3] = {0.05 * unit(rng), 0.04 * unit(rng), L::D == 3 ? 0.03 * unit(rng) : 0.0};
  const double us[3] = {0.01, -0.02, 0.0};
  double f[L::Q], fluid[L::Q], out[L::Q], covered[L::Q], bgk_covered[L::Q];
  for (int q = 0; q < L::Q; ++q)  // zero-centred, off equilibrium
    f[q] = equilibrium<L, Incompressible>(q, 1.01, u) + 1e-3 * L::w[q] * unit(rng);
  std::copy(f, f + L::Q, fluid);
  collide<L, Incompressible>(fluid, p, F);
  double gain[3] = {0, 0, 0};
  psm_collide<L, Incompressible>(f, F, p.omega, p.omega_minus, tau, 0.0, us, out, gain);
  for (int q = 0; q < L::Q; ++q) CHECK(std::abs(out[q] - fluid[q]) < 1e-15);
  psm_collide<L, Incompressible>(f, F, p.omega, p.omega_minus, tau, 1.0, us, covered, gain);
  psm_collide<L, Incompressible>(f, F, p.omega, p.omega, tau, 1.0, us, bgk_covered, gain);
  for (int q = 0; q < L::Q; ++q) CHECK(covered[q] == bgk_covered[q]);
}

}  // namespace

TEST_CASE("a partially saturated cell without solid collides as a fluid cell (BGK and TRT)", "[lbm][psm]") {
  psm_is_the_fluid_collision_without_solid<D3Q19, false>(0.8, true);
  psm_is_the_fluid_collision_without_solid<D3Q19, true>(0.6, true);
  psm_is_the_fluid_collision_without_solid<D3Q19, false>(0.9, false);
  psm_is_the_fluid_collision_without_solid<D2Q9, false>(0.55, true);
  psm_is_the_fluid_collision_without_solid<D2Q9, true>(1.7, false);
}
