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

// x -> scale x + shift for every vertex (a mesh in other units or frame).
void transform(TriangleMesh& m, double scale, const V3& shift);

// What a mesh is: its triangles, bounding box, and whether it is closed (every
// edge shared by exactly two triangles; an open surface is a one-sided wall).
struct MeshSummary {
  std::size_t triangles = 0;
  V3 lower = V3::Zero(), upper = V3::Zero();
  bool closed = false;
  std::size_t open_edges = 0;  // edges of one triangle only
};
MeshSummary summarize(const TriangleMesh& m);

}  // namespace coflow::particles::dem

namespace coflow::particles {

struct WallParams;
// The mesh of a wall: its STL file with the wall's scale and translate
// (particles/params.cpp).
dem::TriangleMesh load_mesh(const WallParams& w);
// "plate.stl: 104972 triangles, box (..) to (..) m, open (12 edges of one triangle)"
std::string describe_mesh(const WallParams& w, const dem::TriangleMesh& m);

}  // namespace coflow::particles
