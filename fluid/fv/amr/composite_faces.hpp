// The faces of every local cell of the composite grid, each with the stencils
// that fv's operators read there: the outward normal derivative and the value
// at the face's centre. A face between cells of one level is one face; a
// face whose other side is finer is split into the 2^(d-1) fine faces, each
// a fraction of the cell's face, with the fine side's stencils negated
// (gradient) or shared (value), so that a flux computed from either side has
// the same bits: fluxes cancel across every face and across levels
// (refluxing built in). On the fine side of a coarse-fine face the ghost
// value is CompositeGrid::coarse_fine_gradient's (Martin & Cartwright 1996).
#pragma once

#include <vector>

#include "fluid/fv/amr/composite_grid.hpp"

namespace coflow::fluid::fv::amr {

struct SubFace {
  int axis = 0;
  int side = 1;           // outward normal: side * e_axis
  double fraction = 1.0;  // of the cell's face area
  bool wall = false;      // on a non-periodic domain face: no stencils
  Stencil gradient;       // d phi / dn, outward (1 / length)
  Stencil value;          // phi at the face's centre
  long across = -1;       // the one cell on the other side (global id; -1 on walls)
  long across_slot = -1;  // where it is in fields gathered with ghosts (CompositeFlow sets it)
  int across_level = 0;   // its level less this cell's: -1, 0 or +1
  Index3 across_index{};  // and its index among its level's cells (periodic images not wrapped)
};

// Per local cell, its sub-faces (ids global).
std::vector<std::vector<SubFace>> build_faces(const CompositeGrid& grid);

}  // namespace coflow::fluid::fv::amr
