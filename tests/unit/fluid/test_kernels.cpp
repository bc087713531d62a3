#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "fluid/lbm/kernels.hpp"

using namespace coflow::fluid::lbm;

namespace {

// Populations of n cells perturbed around equilibria with |u| ~ 0.05, each
// cell pulling along the row.
template <class L, bool Incompressible>
struct Row {
  static constexpr long n = 32;  // population stride
  alignas(64) double src[L::Q * n];
  alignas(64) double dst[L::Q * n];
  long off[L::Q];
  explicit Row(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (long c = 0; c < n; ++c) {
      const double u[3] = {0.05 * unit(rng), 0.05 * unit(rng), L::D == 3 ? 0.05 * unit(rng) : 0.0};
      const double rho = 1.0 + 0.02 * unit(rng);
      for (int q = 0; q < L::Q; ++q)
        src[q * n + c] = equilibrium<L, Incompressible>(q, rho, u) * (1.0 + 0.01 * unit(rng));
    }
    for (int q = 0; q < L::Q; ++q) off[q] = L::e[q][0];  // pull from the row's neighbours
  }
  LineRef ref() { return LineRef{src, dst, n, off}; }
  // The one-cell kernel on cell c's pulled populations.
  double one_cell(long c, const CollisionParams& p, const double* F, double* f) const {
    for (int q = 0; q < L::Q; ++q) f[q] = src[q * n + c - off[q]];
    return collide<L, Incompressible>(f, p, F);
  }
};

// The lean BGK line kernel (no force, eight cells pulled along a row) against
// the one-cell kernel, on populations perturbed around equilibria with
// |u| ~ 0.05, with cached and with streaming stores.
template <class L, bool Incompressible, bool Stream>
void lean_matches_one_cell(double tau) {
  constexpr long x = 8;  // the line's first cell
  std::mt19937_64 rng(7);
  Row<L, Incompressible> row(rng);
  const CollisionParams p = collision_params(tau);
  const double F[3] = {0.0, 0.0, 0.0};
  const Vec4 u2 = bgk_line<L, Incompressible, Stream>(row.ref(), x, p.omega);
#if defined(__AVX__)
  _mm_sfence();
#endif
  for (long c = x; c < x + 8; ++c) {
    double f[L::Q];
    const double u2_one = row.one_cell(c, p, F, f);
    CHECK(u2[(c - x) % 4] >= u2_one * (1.0 - 1e-14));
    // round-off of a few operations on O(0.1) numbers
    for (int q = 0; q < L::Q; ++q) CHECK(std::abs(row.dst[q * row.n + c] - f[q]) < 1e-15);
  }
}

// The general line kernel (TRT, Guo forcing) against the one-cell kernel,
// with a force and tau_minus from the magic parameter.
template <class L, bool Incompressible>
void general_matches_one_cell(double tau, bool trt) {
  constexpr long x = 16;
  std::mt19937_64 rng(11);
  Row<L, Incompressible> row(rng);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const CollisionParams p = collision_params(tau, trt, 0.1875);
  const double F[3] = {1e-3 * unit(rng), 1e-3 * unit(rng), L::D == 3 ? 1e-3 * unit(rng) : 0.0};
  const Vec4 u2 = collide_line<L, Incompressible, false>(row.ref(), x, p, F);
  for (long c = x; c < x + 8; ++c) {
    double f[L::Q];
    const double u2_one = row.one_cell(c, p, F, f);
    CHECK(u2[(c - x) % 4] >= u2_one * (1.0 - 1e-14));
    for (int q = 0; q < L::Q; ++q) CHECK(std::abs(row.dst[q * row.n + c] - f[q]) < 1e-15);
  }
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
