// Triangle meshes from STL files (ASCII or binary): mesh walls of the
// particles, interior solids of the fluid. No FCL here: the schema libraries
// read and check the files at validate.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

namespace coflow::stl {

using V3 = Eigen::Vector3d;

struct TriangleMesh {
  std::vector<V3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

// Reads an STL file; throws std::runtime_error naming the file and the problem
// (a vertex that is not finite among them).
TriangleMesh read(const std::string& path);

// x -> scale x + shift for every vertex (a mesh in other units or frame).
void transform(TriangleMesh& m, double scale, const V3& shift);

// What a mesh is: its triangles, bounding box, and whether it is closed (every
// edge shared by exactly two triangles; an open surface is a one-sided wall).
struct MeshSummary {
  std::size_t triangles = 0;
  V3 lower = V3::Zero(), upper = V3::Zero();
  bool closed = false;
  std::size_t open_edges = 0;  // edges of one triangle only
  // Edges whose two triangles run along them the same way: one of the two is
  // wound the other way round (0 for a consistently wound surface, whose
  // neighbours run along a shared edge in opposite directions).
  std::size_t same_way_edges = 0;
};
MeshSummary summarize(const TriangleMesh& m);

}  // namespace coflow::stl
