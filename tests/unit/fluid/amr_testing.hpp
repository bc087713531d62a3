// What the tests of fv's adaptive grid share: a 2D forest's spec, a worst
// value that NaN cannot hide in, and comparing two runs cell by cell (1 rank
// against N, a restart against a straight run) by level and index.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "fluid/fv/amr/forest.hpp"
#include "tests/unit/worst.hpp"

namespace coflow::test {

// A 2D brick of `trees` with `patch`-cell patches, up to `max_level`,
// `components` values per cell.
inline fluid::fv::amr::ForestSpec forest_2d(std::array<int, 3> trees, std::array<bool, 3> periodic,
                                            int max_level, int patch, int components) {
  fluid::fv::amr::ForestSpec s;
  s.dims = 2;
  s.trees = trees;
  s.periodic = periodic;
  s.max_level = max_level;
  s.patch = patch;
  s.components = components;
  return s;
}

// Refinement toward (2.5, 3.6) on a brick of trees of pi/2: a leaf of level
// 0 refines within 1.2 of it, one of level 1 within 0.6 (the test vortex's
// forest: its coarse-fine faces cross the flow).
inline bool refine_near_vortex(int level, const fluid::fv::amr::Index3& p) {
  const double size = 0.5 * 3.14159265358979323846 / (1 << level), c[2] = {2.5, 3.6};
  double r2 = 0.0;
  for (int d = 0; d < 2; ++d) {
    const double lo = static_cast<double>(p[d]) * size;
    const double q = std::clamp(c[d], lo, lo + size) - c[d];
    r2 += q * q;
  }
  const double radius = level == 0 ? 1.2 : 0.6;
  return r2 < radius * radius;
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
