// One rank's block of the fluid grid: its owned cells (a box of the global
// grid) and `ghost` layers of cells around them on every axis that has more
// than one cell. Cells are addressed owned-relative: (0, 0, 0) is the first
// owned cell, -ghost..-1 and extent..extent+ghost-1 are ghosts; a cell field
// stores them x fastest, `components` values per cell.
#pragma once

#include "coflow/decomposition.hpp"

namespace coflow::fluid::grid {

struct Block {
  coupler::Box owned;               // global cell indices
  coupler::Index3 extent{1, 1, 1};  // owned cells per axis
  coupler::Index3 ghost{0, 0, 0};   // ghost layers per axis

  // Block `rank` of `dec` with `width` ghost layers (none on one-cell axes).
  static Block of(const coupler::Decomposition& dec, int rank, int width) {
    Block b;
    b.owned = dec.block(rank);
    b.ghost = dec.ghost(width);
    for (int d = 0; d < 3; ++d) b.extent[d] = b.owned.extent(d);
    return b;
  }
  long padded(int d) const { return extent[d] + 2 * ghost[d]; }
  long cells() const { return padded(0) * padded(1) * padded(2); }  // owned and ghost
  long owned_cells() const { return extent[0] * extent[1] * extent[2]; }
  long idx(long i, long j, long k) const {
    return ((k + ghost[2]) * padded(1) + (j + ghost[1])) * padded(0) + (i + ghost[0]);
  }
};

}  // namespace coflow::fluid::grid
