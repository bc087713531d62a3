// Snapshots of fv's adaptive grid for ParaView: one HDF5 file and one XDMF
// file per snapshot, the XDMF a spatial collection of one unstructured grid
// per level (quadrilaterals in 2D, hexahedra in 3D, each cell with its own
// corners), with the cells' fields and their level as cell data. ParaView
// shows the levels as blocks and can colour by "level".
#pragma once

#include <string>
#include <vector>

#include "fluid/fv/amr/composite_grid.hpp"

namespace coflow::fluid::fv::amr {

// `components` values per cell from the forest's component `first`, times
// `scale`, or from `values` (per local cell, `components` each) where given
// (2D vectors are written with a zero third component).
struct CompositeField {
  std::string name;
  int first = 0;
  int components = 1;
  double scale = 1.0;
  std::vector<double> values = {};
};

// Collective over the forest's ranks: writes <dir>/<stem>.h5 and
// <dir>/<stem>.xmf (rank 0). The forest's values as they are (no ghosts
// needed).
void write_composite(const CompositeGrid& grid, const std::string& dir, const std::string& stem, double time,
                     long step, const std::vector<CompositeField>& fields);

}  // namespace coflow::fluid::fv::amr
