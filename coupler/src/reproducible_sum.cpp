#include "coflow/reproducible_sum.hpp"

#include <bit>
#include <cmath>
#include <stdexcept>

namespace coflow::coupler {

namespace {

constexpr int kLevels = 3;

// The grids of a column whose terms are all below 2^e in magnitude, n of
// them: level k rounds to multiples of 2^(K_k - 52) through sigma_k = 1.5 *
// 2^K_k, so that sigma + x stays in sigma's binade for |x| < 2^(K_k - 1) and
// (sigma + x) - sigma is x rounded to that grid, exactly. n terms of at most
// 2^e sum to below 2^(K_1 - 1), exact on the grid; each remainder is at most
// half a grid step, the next level's 2^e.
struct Grids {
  double sigma[kLevels] = {0, 0, 0};
  bool on[kLevels] = {false, false, false};
  Grids(double largest, unsigned long long n) {
    int e = 0;
    std::frexp(largest, &e);                 // largest < 2^e
    const int bits = std::bit_width(n) + 1;  // 2^bits > 2n
    for (int k = 0; k < kLevels; ++k) {
      const int K = e + bits;
      on[k] = K - 52 > -1022;  // the grid step a normal number
      sigma[k] = on[k] ? 1.5 * std::ldexp(1.0, K) : 0.0;
      e = K - 53;
    }
  }
};

}  // namespace

std::vector<double> reproducible_sums(MPI_Comm comm, std::span<const double> terms, int width) {
  if (width <= 0 || terms.size() % static_cast<std::size_t>(width) != 0)
    throw std::logic_error("reproducible_sums: the terms are not rows of `width`");
  const auto w = static_cast<std::size_t>(width);
  const std::size_t rows = terms.size() / w;
  std::vector<double> largest(w, 0.0);  // the largest |term| of each column (infinity: not finite)
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < w; ++c) {
      const double a = std::fabs(terms[r * w + c]);
      // Beyond 2^960 the grids would overflow: such a column takes the plain sum.
      largest[c] = a < 0x1p960 ? std::fmax(largest[c], a) : HUGE_VAL;
    }
  unsigned long long n = rows;
  MPI_Allreduce(MPI_IN_PLACE, largest.data(), width, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
  // Per column: the levels' exact sums, then the plain sum (for a column
  // that is not finite).
  const std::size_t per = kLevels + 1;
  std::vector<double> sums(per * w, 0.0);
  for (std::size_t c = 0; c < w; ++c) {
    double* s = &sums[per * c];
    if (!std::isfinite(largest[c])) {  // a NaN, an infinity or a term beyond 2^960
      for (std::size_t r = 0; r < rows; ++r) s[kLevels] += terms[r * w + c];
      continue;
    }
    if (largest[c] == 0.0) continue;
    const Grids g(largest[c], n);
    for (std::size_t r = 0; r < rows; ++r) {
      double x = terms[r * w + c];
      for (int k = 0; k < kLevels && g.on[k]; ++k) {
        const double q = (g.sigma[k] + x) - g.sigma[k];
        s[k] += q;
        x -= q;
      }
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM, comm);
  std::vector<double> out(w);
  for (std::size_t c = 0; c < w; ++c) {
    const double* s = &sums[per * c];
    out[c] = std::isfinite(largest[c]) ? (s[0] + s[1]) + s[2] : s[kLevels];
  }
  return out;
}

}  // namespace coflow::coupler
