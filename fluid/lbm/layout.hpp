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
  // The streaming offset, in cells, of a population with lattice velocity e.
  // An axis without ghosts has one cell, periodic (D3Q19 on one cell along z,
  // lbm::LbmParams::check): a population moving along it wraps onto its own
  // cell, so that axis adds nothing.
  long offset(const int (&e)[3]) const {
    const long ex = ghost[0] ? e[0] : 0, ey = ghost[1] ? e[1] : 0, ez = ghost[2] ? e[2] : 0;
    return ex + padded[0] * (ey + padded[1] * ez);
  }
};

}  // namespace coflow::fluid::lbm
