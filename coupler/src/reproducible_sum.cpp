#include "coflow/reproducible_sum.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "coflow/mpi_count.hpp"

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

ExactSums::ExactSums(std::size_t n) : digits_(kDigits * n, 0), special_(n, 0.0) {}

void ExactSums::add(std::size_t i, double x) {
  if (!std::isfinite(x)) {
    special_.at(i) += x;
    return;
  }
  if (x == 0.0) return;
  // x = m 2^(p - 1074) with m < 2^53 a whole number and p >= 0, read from
  // its bits: a normal number's biased exponent b gives p = b - 1 and the
  // hidden bit; a subnormal's (b = 0) is m 2^-1074 as it stands.
  const auto bits = std::bit_cast<std::uint64_t>(x);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  std::uint64_t m = bits & ((std::uint64_t{1} << 52) - 1);
  int p = 0;
  if (biased > 0) m |= std::uint64_t{1} << 52, p = biased - 1;
  // m's two 32-bit halves shifted into place: each below 2^64, the low one
  // reaching digits k and k + 1, the high one k + 1 and k + 2.
  const int shift = p % 32;
  const std::uint64_t low = (m & 0xffffffffu) << shift, high = (m >> 32) << shift;
  const std::int64_t sign = x < 0 ? -1 : 1;
  std::int64_t* d = &digits_.at(kDigits * i + static_cast<std::size_t>(p / 32));  // p / 32 <= 65
  d[0] += sign * static_cast<std::int64_t>(low & 0xffffffffu);
  d[1] += sign * static_cast<std::int64_t>((low >> 32) + (high & 0xffffffffu));
  d[2] += sign * static_cast<std::int64_t>(high >> 32);
  if (++adds_ == (std::int64_t{1} << 28)) carry();  // each digit moves by < 2^33 an add
}

void ExactSums::merge(ExactSums other) {
  if (other.size() != size()) throw std::logic_error("exact sums of another size merged");
  other.carry();  // every digit but the top one in [0, 2^32): as one add of < 2^33 a digit
  for (std::size_t k = 0; k < digits_.size(); ++k) digits_[k] += other.digits_[k];
  for (std::size_t i = 0; i < size(); ++i) special_[i] += other.special_[i];
  if (++adds_ == (std::int64_t{1} << 28)) carry();
}

namespace {

// One value's n digits carried into canonical form: each but the top one in
// [0, 2^32), the top one signed.
void carry_digits(std::int64_t* d, int n) {
  for (int k = 0; k + 1 < n; ++k) {
    const std::int64_t c = d[k] >> 32;  // floor(d / 2^32)
    d[k] -= c * (std::int64_t{1} << 32);
    d[k + 1] += c;
  }
}

// The canonical digits of a value as a double: its magnitude from the top
// digit down, then its sign. The same digits give the same bits; the error
// is a few units in the last place.
double to_double(std::int64_t* d, int n) {
  const bool negative = d[n - 1] < 0;
  if (negative) {  // the digits of -value, canonical again
    for (int k = 0; k < n; ++k) d[k] = -d[k];
    carry_digits(d, n);
  }
  double r = 0.0;
  for (int k = n - 1; k >= 0; --k)
    if (d[k] != 0) r += std::ldexp(static_cast<double>(d[k]), 32 * k - 1074);
  return negative ? -r : r;
}

}  // namespace

void ExactSums::carry() {
  for (std::size_t i = 0; i < size(); ++i) carry_digits(&digits_[kDigits * i], kDigits);
  adds_ = 0;
}

void ExactSums::to_root(MPI_Comm comm) {
  carry();
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const int n = mpi_count(digits_.size(), "exact sums"), m = mpi_count(special_.size(), "exact sums");
  MPI_Reduce(rank == 0 ? MPI_IN_PLACE : digits_.data(), digits_.data(), n, MPI_INT64_T, MPI_SUM, 0, comm);
  MPI_Reduce(rank == 0 ? MPI_IN_PLACE : special_.data(), special_.data(), m, MPI_DOUBLE, MPI_SUM, 0, comm);
  if (rank == 0) {
    carry();
    return;
  }
  std::fill(digits_.begin(), digits_.end(), 0);
  std::fill(special_.begin(), special_.end(), 0.0);
}

std::vector<std::int64_t> ExactSums::canonical(std::size_t i) {
  carry();
  return {digits_.begin() + static_cast<std::ptrdiff_t>(kDigits * i),
          digits_.begin() + static_cast<std::ptrdiff_t>(kDigits * (i + 1))};
}

void ExactSums::set(std::size_t i, const std::vector<std::int64_t>& digits, double special) {
  if (digits.size() != static_cast<std::size_t>(kDigits))
    throw std::invalid_argument("exact sums: not 68 digits");
  std::copy(digits.begin(), digits.end(), digits_.begin() + static_cast<std::ptrdiff_t>(kDigits * i));
  special_.at(i) = special;
  carry();
}

std::vector<double> ExactSums::reduce(MPI_Comm comm) {
  carry();
  MPI_Allreduce(MPI_IN_PLACE, digits_.data(), mpi_count(digits_.size(), "exact sums"), MPI_INT64_T, MPI_SUM,
                comm);
  MPI_Allreduce(MPI_IN_PLACE, special_.data(), mpi_count(special_.size(), "exact sums"), MPI_DOUBLE, MPI_SUM,
                comm);
  carry();
  std::vector<double> out(size());
  for (std::size_t i = 0; i < size(); ++i)
    out[i] = special_[i] != 0.0 || std::isnan(special_[i]) ? special_[i]
                                                           : to_double(&digits_[kDigits * i], kDigits);
  std::fill(digits_.begin(), digits_.end(), 0);
  std::fill(special_.begin(), special_.end(), 0.0);
  return out;
}

}  // namespace coflow::coupler
