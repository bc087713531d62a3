// Where the populations of one rank's block live: the owned cells plus one
// ghost layer on every axis that has more than one cell, rows padded to whole
// cache lines and shifted so that the interior rows start on a 64-byte
// boundary (streaming stores); population q of local cell x at q * stride + x.
#pragma once

namespace coflow::fluid::lbm {

struct Layout {
  long origin[3] = {0, 0, 0};  // global index of the first owned cell
  long extent[3] = {1, 1, 1};  // owned cells per axis
  long ghost[3] = {0, 0, 0};   // ghost cells on each side, per axis (0 or 1)
  long padded[3] = {1, 1, 1};  // allocated cells per axis (x: padded to a multiple of 8)
  long shift = 0;              // cells before the first allocated one (alignment)
  long stride = 0;             // distance between two populations of one cell
  // Local index of owned cell (i, j, k); -1 and extent are the ghosts.
  long idx(long i, long j, long k) const {
    return shift + ((k + ghost[2]) * padded[1] + (j + ghost[1])) * padded[0] + (i + ghost[0]);
  }
};

}  // namespace coflow::fluid::lbm
