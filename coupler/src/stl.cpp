#include "coflow/stl.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "coflow/config.hpp"

namespace coflow::stl {

TriangleMesh read(const std::string& path) {
  if (const std::string why = config::file_problem(path); !why.empty())
    throw std::runtime_error(fmt::format("{}: {} (an STL mesh file was expected)", path, why));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the mesh file", path));
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  TriangleMesh m;
  auto add = [&](const V3& a, const V3& b, const V3& c) {
    if (!(a.allFinite() && b.allFinite() && c.allFinite()))
      throw std::runtime_error(
          fmt::format("{}: triangle {} has a vertex that is not finite", path, m.triangles.size() + 1));
    const int base = static_cast<int>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {a, b, c});
    m.triangles.push_back({base, base + 1, base + 2});
  };
  // Binary: 80-byte header, uint32 count, 50 bytes per triangle.
  if (data.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() == 84 + 50ull * n) {
      for (std::uint32_t t = 0; t < n; ++t) {
        float v[12];
        std::memcpy(v, data.data() + 84 + 50ull * t, sizeof v);
        add(V3(v[3], v[4], v[5]), V3(v[6], v[7], v[8]), V3(v[9], v[10], v[11]));
      }
      if (n == 0) throw std::runtime_error(fmt::format("{}: the binary STL holds no triangle", path));
      return m;
    }
  }
  std::istringstream s(data);
  std::string word;
  s >> word;
  if (word != "solid")
    throw std::runtime_error(fmt::format("{}: neither a binary STL (size does not match its triangle count) nor "
                                         "an ASCII STL (does not start with 'solid')",
                                         path));
  std::vector<V3> corners;
  while (s >> word) {
    if (word != "vertex") continue;
    V3 v;
    if (!(s >> v[0] >> v[1] >> v[2]))
      throw std::runtime_error(fmt::format("{}: a vertex line without three numbers", path));
    corners.push_back(v);
    if (corners.size() == 3) {
      add(corners[0], corners[1], corners[2]);
      corners.clear();
    }
  }
  if (!corners.empty()) throw std::runtime_error(fmt::format("{}: a facet with fewer than three vertices", path));
  if (m.triangles.empty()) throw std::runtime_error(fmt::format("{}: the ASCII STL holds no facet", path));
  return m;
}

void transform(TriangleMesh& m, double scale, const V3& shift) {
  for (auto& x : m.vertices) x = scale * x + shift;
}

MeshSummary summarize(const TriangleMesh& m) {
  MeshSummary s;
  s.triangles = m.triangles.size();
  if (!m.vertices.empty()) s.lower = s.upper = m.vertices.front();
  for (const auto& x : m.vertices) {
    s.lower = s.lower.cwiseMin(x);
    s.upper = s.upper.cwiseMax(x);
  }
  // Vertices are matched by position (an STL repeats them per facet).
  std::map<std::array<double, 3>, int> id;
  auto key = [&](int v) {
    const auto& x = m.vertices[static_cast<std::size_t>(v)];
    return id.emplace(std::array<double, 3>{x[0], x[1], x[2]}, static_cast<int>(id.size())).first->second;
  };
  // Each edge: the triangles that hold it, and the sum of the ways they run
  // along it (+1 from the lower vertex id to the higher, -1 back).
  std::map<std::pair<int, int>, std::array<int, 2>> edges;
  for (const auto& t : m.triangles)
    for (int e = 0; e < 3; ++e) {
      const int a = key(t[e]), b = key(t[(e + 1) % 3]);
      auto& [count, way] = edges[{std::min(a, b), std::max(a, b)}];
      ++count;
      way += a < b ? 1 : -1;
    }
  bool two = !edges.empty();
  for (const auto& [edge, c] : edges) {
    two = two && c[0] == 2;
    if (c[0] == 1) ++s.open_edges;
    if (c[0] == 2 && c[1] != 0) ++s.same_way_edges;
  }
  s.closed = two;
  return s;
}

}  // namespace coflow::stl
