// Comparing two runs of fv's adaptive grid cell by cell (1 rank against N, a
// restart against a straight run): their values keyed by level and index.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace coflow::test {

// The larger of a worst value so far and a new one; a NaN makes it infinite
// (std::max would drop it), so that a bound check sees it.
inline double worst_of(double so_far, double value) {
  return std::isnan(value) ? HUGE_VAL : std::max(so_far, value);
}

// The largest |a - b| over this rank's cells of `a`, reduced over `comm`
// (NaN counts as infinite); *missing: the cells of `a` that `b` lacks, summed
// over `comm`. Every rank must call it.
template <class Key>
double largest_difference(const std::map<Key, double>& a, const std::map<Key, double>& b, long* missing,
                          MPI_Comm comm = MPI_COMM_WORLD) {
  double worst = 0.0;
  long absent = 0;
  for (const auto& [key, v] : a) {
    const auto it = b.find(key);
    if (it == b.end()) {
      ++absent;
      continue;
    }
    worst = worst_of(worst, std::fabs(v - it->second));
  }
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(&absent, missing, 1, MPI_LONG, MPI_SUM, comm);
  return worst;
}

}  // namespace coflow::test
