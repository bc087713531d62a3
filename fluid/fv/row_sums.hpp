// Sums over one row of n cells in four partial sums, lane i mod 4 (four
// independent chains of adds where one chain waits four cycles per add, and
// a form the compiler vectorises), added pairwise at the end: the order is
// fixed by the row's length alone.
#pragma once

namespace coflow::fluid::fv {

// term(i, a) adds cell i's terms to a[0 .. count - 1] (count at most 2).
template <class Term>
void row_sums(long n, double* sum, int count, Term term) {
  double part[4][2] = {};
  long i = 0;
  for (; i + 4 <= n; i += 4)
    for (int l = 0; l < 4; ++l) term(i + l, part[l]);
  for (; i < n; ++i) term(i, part[0]);
  for (int c = 0; c < count; ++c) sum[c] += (part[0][c] + part[1][c]) + (part[2][c] + part[3][c]);
}

}  // namespace coflow::fluid::fv
