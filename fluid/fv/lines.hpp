// The lines of a padded block along one axis: what fv's boundary conditions
// (boundaries.cpp, turbulence/k_epsilon.cpp) loop over to fill the ghosts
// beyond a face.
#pragma once

#include <cstddef>

#include "fluid/grid/block.hpp"

namespace coflow::fluid::fv {

// f(index, line) for every line along axis a of the padded block; index(m)
// is the cell at m along a on that line (owned-relative, ghosts negative or
// >= n), line its owned-relative coordinates (0 along a).
template <class F>
void for_lines(const grid::Block& b, int a, F&& f) {
  const int o1 = (a + 1) % 3, o2 = (a + 2) % 3;
  for (long s = -b.ghost[o2]; s < b.extent[o2] + b.ghost[o2]; ++s)
    for (long r = -b.ghost[o1]; r < b.extent[o1] + b.ghost[o1]; ++r) {
      long line[3];
      line[a] = 0;
      line[o1] = r;
      line[o2] = s;
      f(
          [&](long m) {
            long at[3] = {line[0], line[1], line[2]};
            at[a] = m;
            return static_cast<std::size_t>(b.idx(at[0], at[1], at[2]));
          },
          static_cast<const long*>(line));
    }
}

}  // namespace coflow::fluid::fv
