// Triangle meshes from STL files (ASCII or binary), for mesh walls. Part of the
// particles schema library: validation reads the files, without FCL.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "particles/dem/contact.hpp"

namespace coflow::particles::dem {

struct TriangleMesh {
  std::vector<V3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

// Reads an STL file; throws std::runtime_error naming the file and the problem.
TriangleMesh read_stl(const std::string& path);

}  // namespace coflow::particles::dem
