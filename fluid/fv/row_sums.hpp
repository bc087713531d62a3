// Sums over one row of n cells in eight partial sums, lane i mod 8 for the
// first n - n mod 8 cells and lane 0 for the rest (eight independent chains of
// adds where one chain waits four cycles per add, held side by side so that
// they fill one 512-bit or two 256-bit registers), added pairwise at the end:
// the order is fixed by the row's length alone.
#pragma once

namespace coflow::fluid::fv {

inline constexpr int kRowSumLanes = 8;

// One lane's sums: a[c] is the lane's sum c.
struct RowSumLane {
  double* p;
  double& operator[](int c) const { return p[c * kRowSumLanes]; }
};

// term(i, a) adds cell i's terms to a[0 .. count - 1] (count at most 2).
template <class Term>
void row_sums(long n, double* sum, int count, Term term) {
  constexpr int L = kRowSumLanes;
  double part[2 * L] = {};
  long i = 0;
  for (; i + L <= n; i += L)
    for (int l = 0; l < L; ++l) term(i + l, RowSumLane{part + l});
  for (; i < n; ++i) term(i, RowSumLane{part});
  for (int c = 0; c < count; ++c) {
    const double* q = part + c * L;
    sum[c] += ((q[0] + q[1]) + (q[2] + q[3])) + ((q[4] + q[5]) + (q[6] + q[7]));
  }
}

}  // namespace coflow::fluid::fv
