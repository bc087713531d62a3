// Sums over the ranks whose bits do not depend on the order of the terms or
// on how they are split among the ranks: 1 rank gives the same sums as N.
// Each term is pre-rounded to a grid set by the largest term on any rank and
// by the number of terms, fine enough that every partial sum on that grid is
// exact (Demmel & Nguyen 2015, "Parallel reproducible summation", IEEE Trans.
// Comput. 64(7), 2060-2070, §III). Three such levels, each taking the
// remainder of the one before, are summed exactly and added in a fixed order
// at the end. The error is at most n 2^(e + 3b - 159) (n terms, b =
// bit_width(n) + 1, all terms below 2^e): about 1e-23 of the largest term for
// a million terms, below a double's own rounding of the sum.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace coflow::coupler {

// `terms` holds n rows of `width` terms (row-major); returns the `width`
// column sums, the same on every rank (collective: three reductions). A
// column with a NaN, an infinity or a term beyond 2^960 anywhere gives the
// plain sum.
std::vector<double> reproducible_sums(MPI_Comm comm, std::span<const double> terms, int width);

// Running sums kept exactly, for terms that arrive one at a time over a
// window (a wall's impulses, contact by contact and step by step): each value
// is an integer multiple of 2^-1074, the smallest double, held as 68 signed
// 32-bit digits in int64 words, so that adding a double is exact and the sum
// does not depend on the order of the terms or on how they are split among
// the ranks. The reduction adds the ranks' digits as integers (exact), brings
// the digits to the one canonical form of the integer and rounds that to a
// double the same way on every rank: 1 rank gives the same bits as N. A NaN
// or an infinity among the terms gives the plain sum of those terms.
class ExactSums {
 public:
  explicit ExactSums(std::size_t n = 0);
  std::size_t size() const { return special_.size(); }
  void add(std::size_t i, double x);
  // Adds another's sums (of the same size), exactly.
  void merge(ExactSums other);
  // Collective over comm: the sums of every rank's terms, rounded to
  // doubles, the same bits on every rank. Zeroes these sums.
  std::vector<double> reduce(MPI_Comm comm);
  // Collective over comm: every rank's sums gathered, exactly, on rank 0;
  // the other ranks' zeroed (a later reduce gives the same doubles).
  void to_root(MPI_Comm comm);
  // Value i's digits in their canonical form (each but the top one in
  // [0, 2^32)), and the plain sum of its non-finite terms; set() puts them
  // back (a checkpoint's).
  std::vector<std::int64_t> canonical(std::size_t i);
  double special(std::size_t i) const { return special_.at(i); }
  void set(std::size_t i, const std::vector<std::int64_t>& digits, double special);
  static constexpr int kDigits = 68;  // 2^-1074 to past 2^1100 in 32-bit digits

 private:
  void carry();                       // each digit but the top one into [0, 2^32)
  std::vector<std::int64_t> digits_;  // value i: digits_[kDigits i + k] 2^(32 k - 1074)
  std::vector<double> special_;       // the plain sum of the non-finite terms
  std::int64_t adds_ = 0;             // since the last carry
};

}  // namespace coflow::coupler
