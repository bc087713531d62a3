// Triangle meshes of mesh walls (coflow/stl.hpp reads them), and a wall's mesh
// with its scale and translate. Part of the particles schema library.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "coflow/stl.hpp"
#include "particles/dem/contact.hpp"

namespace coflow::particles::dem {

// The mesh reader is the coupler's (coflow/stl.hpp), shared with the fluid's
// interior solids.
using stl::MeshSummary;
using stl::summarize;
using stl::transform;
using stl::TriangleMesh;
inline TriangleMesh read_stl(const std::string& path) { return stl::read(path); }

}  // namespace coflow::particles::dem

namespace coflow::particles {

struct WallParams;
// The mesh of a wall: its STL file with the wall's scale and translate
// (particles/params.cpp).
dem::TriangleMesh load_mesh(const WallParams& w);
// "plate.stl: 104972 triangles, box (..) to (..) m, open (12 edges of one triangle)"
std::string describe_mesh(const WallParams& w, const dem::TriangleMesh& m);

}  // namespace coflow::particles
