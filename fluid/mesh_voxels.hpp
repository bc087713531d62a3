// A closed triangle mesh on the fluid grid: which cells' centres it holds
// (fluid.solids, kind mesh). Part of the fluid schema library.
#pragma once

#include <cstdint>
#include <vector>

#include "coflow/run_config.hpp"
#include "coflow/stl.hpp"

namespace coflow::fluid {

// Per cell (x fastest) 1 where the cell's centre is inside the closed mesh,
// else 0: along each row of centres in x, the crossings of the ray with the
// triangles (projected on y-z) toggle inside and outside (parity). The ray is
// moved off the grid by a tiny irrational offset, so that it meets no edge or
// vertex of a mesh built on the grid's own coordinates.
std::vector<std::uint8_t> mesh_voxels(const stl::TriangleMesh& mesh, const config::DomainParams& domain);

}  // namespace coflow::fluid
