// The neighbours of one rank's block across its faces, edges and corners, for
// a ghost layer of a given width: which rank owns the cells beyond each side
// (periodic images included; none beyond a wall of the domain), the owned
// cells it needs from this block and the ghost cells this block receives from
// it. Every ghost exchange on the fluid grid walks this list (the lbm halo of
// populations and the ghost exchange of cell fields).
#pragma once

#include <vector>

#include "coflow/decomposition.hpp"

namespace coflow::fluid::grid {

struct Neighbour {
  int rank = -1;                 // may be this rank (a periodic axis not split)
  int d[3] = {0, 0, 0};          // direction, each -1, 0 or 1
  coupler::Box send, recv;       // owned-relative: owned cells sent, ghost cells received
  // When the neighbour is this block itself (a periodic axis not split), sent
  // cell c lands in ghost c - period.
  coupler::Index3 period{0, 0, 0};
};

// In the order dz, dy, dx from -1 to 1 (x fastest). Throws when a block is
// thinner than the ghost layer along a split or periodic axis (the ghosts
// would come from a second rank).
std::vector<Neighbour> neighbours(const coupler::Decomposition& dec, int rank, const coupler::Index3& ghost);

}  // namespace coflow::fluid::grid
