#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

#include "particles/dem/mesh.hpp"

using namespace coflow::particles::dem;

namespace {
std::string temp(const std::string& name) { return std::string(std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp") + "/" + name; }

void write_binary(const std::string& path, const std::vector<std::array<float, 9>>& tris) {
  std::ofstream out(path, std::ios::binary);
  char header[80] = "binary test mesh";
  out.write(header, 80);
  const std::uint32_t n = static_cast<std::uint32_t>(tris.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : tris) {
    const float normal[3] = {0, 0, 1};
    out.write(reinterpret_cast<const char*>(normal), 12);
    out.write(reinterpret_cast<const char*>(t.data()), 36);
    const std::uint16_t attr = 0;
    out.write(reinterpret_cast<const char*>(&attr), 2);
  }
}
}  // namespace

TEST_CASE("STL files are read in ASCII and binary form alike", "[mesh]") {
  const std::string a = temp("coflow-test-ascii.stl"), b = temp("coflow-test-binary.stl");
  std::ofstream(a) << "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n"
                      "  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n   vertex 1 1 0\n"
                      "   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n";
  write_binary(b, {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}});
  const TriangleMesh ma = read_stl(a), mb = read_stl(b);
  REQUIRE(ma.triangles.size() == 2);
  REQUIRE(mb.triangles.size() == 2);
  for (std::size_t v = 0; v < ma.vertices.size(); ++v) CHECK((ma.vertices[v] - mb.vertices[v]).norm() == 0.0);
  std::remove(a.c_str());
  std::remove(b.c_str());
}

TEST_CASE("malformed STL files are rejected with the file name", "[mesh]") {
  const std::string bad = temp("coflow-test-bad.stl");
  std::ofstream(bad) << "this is not a mesh\n";
  CHECK_THROWS_WITH(read_stl(bad), Catch::Contains("coflow-test-bad.stl") && Catch::Contains("neither a binary"));
  std::ofstream(bad) << "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0\n";
  CHECK_THROWS(read_stl(bad));
  CHECK_THROWS_WITH(read_stl(temp("coflow-no-such-file.stl")),
                    Catch::Contains("coflow-no-such-file.stl: no such file"));
  // A binary vertex that is not finite (before 2026-12-05 it went through,
  // and the checks after it compared NaN, which is false either way).
  write_binary(bad, {{0, 0, 0, 1, 0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0}});
  CHECK_THROWS_WITH(read_stl(bad), Catch::Contains("triangle 1 has a vertex that is not finite"));
  std::remove(bad.c_str());
}

TEST_CASE("closest point on a triangle: face, edge and vertex regions", "[mesh]") {
  const V3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  bool face = false;
  CHECK((closest_on_triangle(V3(0.2, 0.3, 0.5), a, b, c, face) - V3(0.2, 0.3, 0)).norm() < 1e-15);
  CHECK(face);
  CHECK((closest_on_triangle(V3(0.5, -0.4, 0.1), a, b, c, face) - V3(0.5, 0, 0)).norm() < 1e-15);
  CHECK_FALSE(face);
  CHECK((closest_on_triangle(V3(-1, -1, 1), a, b, c, face) - a).norm() < 1e-15);
  CHECK_FALSE(face);
}

TEST_CASE("a flat mesh acts as one plane: one contact, whichever triangles", "[mesh]") {
  // Two triangles sharing the diagonal; a sphere over the diagonal, over one
  // face near the diagonal, and over the shared corner.
  TriangleMesh m;
  m.vertices = {V3(0, 0, 0), V3(1, 0, 0), V3(1, 1, 0), V3(0, 1, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  const MeshWall wall(m, 0.3);
  std::vector<MeshContact> hits, all;
  for (const V3& x : {V3(0.5, 0.5, 0.05), V3(0.52, 0.48, 0.05), V3(0.0, 0.0, 0.05), V3(0.3, 0.7, 0.08)}) {
    wall.contacts(x, 0.1, hits);
    wall.contacts_all(x, 0.1, all);
    REQUIRE(hits.size() == 1);
    REQUIRE(all.size() == 1);
    CHECK(hits[0].triangle == all[0].triangle);
    CHECK(std::abs(hits[0].point.z()) < 1e-15);
    CHECK(std::abs((x - hits[0].point).norm() - x.z()) < 1e-12);  // distance to the plane
  }
  wall.contacts(V3(0.5, 0.5, 0.2), 0.1, hits);
  CHECK(hits.empty());
}

TEST_CASE("mesh summary: triangles, box, closedness; scale and translate", "[mesh]") {
  // A tetrahedron is closed: each of its 6 edges belongs to 2 of its 4 faces.
  TriangleMesh tet;
  tet.vertices = {V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(0, 0, 1)};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  MeshSummary s = summarize(tet);
  CHECK(s.triangles == 4);
  CHECK(s.closed);
  CHECK(s.open_edges == 0);
  CHECK(s.same_way_edges == 0);
  // One face wound the other way round: its three edges run the same way as
  // in the faces next to it (before 2026-12-05 only the volume's sign was
  // checked, and a face through the origin adds no volume).
  tet.triangles[0] = {0, 1, 2};
  s = summarize(tet);
  CHECK(s.closed);
  CHECK(s.same_way_edges == 3);
  tet.triangles[0] = {0, 2, 1};
  // Without one face it is open: the three edges of the missing face are single.
  tet.triangles.pop_back();
  s = summarize(tet);
  CHECK_FALSE(s.closed);
  CHECK(s.open_edges == 3);
  // A mesh drawn in millimetres, brought to metres and moved: x -> 0.001 x + (1, 2, 3).
  transform(tet, 0.001, V3(1, 2, 3));
  s = summarize(tet);
  CHECK(s.lower.isApprox(V3(1, 2, 3), 1e-15));
  CHECK(s.upper.isApprox(V3(1.001, 2.001, 3.001), 1e-15));
}

// Found by a read-only review (2026-12-05). Before, a face contact anywhere on
// the mesh dropped every edge and vertex contact (a sphere on a floor went
// through the edge of a post of the same mesh), and with no face contact every
// distinct edge or vertex point counted (the corner of a square cut in two
// triangles gave a second, vertex contact beside the edge's).
TEST_CASE("mesh contacts: a post's edge beside a floor's face; one contact at a cut square's rim", "[mesh]") {
  // A floor cut along its diagonal, and a cube [0, 0.2]^3 standing on it
  // (its four side faces, two triangles each, outward).
  TriangleMesh m;
  m.vertices = {V3(-1, -1, 0), V3(1, -1, 0), V3(1, 1, 0), V3(-1, 1, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  const auto quad = [&](V3 a, V3 b, V3 c, V3 d) {  // a b c d counter-clockwise seen from outside
    const int n = static_cast<int>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {a, b, c, d});
    m.triangles.push_back({n, n + 1, n + 2});
    m.triangles.push_back({n, n + 2, n + 3});
  };
  const double s = 0.2;
  quad(V3(0, 0, 0), V3(0, 0, s), V3(0, s, s), V3(0, s, 0));  // x = 0, outward -x
  quad(V3(0, 0, 0), V3(s, 0, 0), V3(s, 0, s), V3(0, 0, s));  // y = 0, outward -y
  const MeshWall wall(m, 0.3);
  std::vector<MeshContact> hits, all;
  // Sphere r = 0.05 at (-0.03, -0.03, 0.049): the floor's face 0.049 below,
  // the post's vertical edge x = y = 0 at 0.0424.
  const V3 x(-0.03, -0.03, 0.049);
  wall.contacts(x, 0.05, hits);
  wall.contacts_all(x, 0.05, all);
  REQUIRE(hits.size() == 2);
  REQUIRE(all.size() == 2);
  V3 push = V3::Zero();
  for (const auto& h : hits) push += (0.05 - (x - h.point).norm()) * (x - h.point).normalized();
  CHECK(std::abs(push.z() - 0.001) < 1e-12);  // the floor's overlap
  const double edge = 0.05 - std::sqrt(2.0) * 0.03;
  CHECK(std::abs(push.x() + edge / std::sqrt(2.0)) < 1e-12);  // the edge's, along (-1, -1, 0) / sqrt 2
  CHECK(std::abs(push.y() + edge / std::sqrt(2.0)) < 1e-12);

  // A square cut along its diagonal, a sphere beyond its edge y = 0 near the
  // corner (0, 0, 0): one contact, on the edge.
  TriangleMesh sq;
  sq.vertices = {V3(0, 0, 0), V3(1, 0, 0), V3(1, 1, 0), V3(0, 1, 0)};
  sq.triangles = {{0, 1, 2}, {0, 2, 3}};
  const MeshWall flat(sq, 0.3);
  flat.contacts(V3(0.05, -0.05, 0.05), 0.1, hits);
  flat.contacts_all(V3(0.05, -0.05, 0.05), 0.1, all);
  REQUIRE(hits.size() == 1);
  REQUIRE(all.size() == 1);
  CHECK((hits[0].point - V3(0.05, 0, 0)).norm() < 1e-15);
}

// The rule's tolerance (a second read, 2026-12-05): the two triangles of a
// ridge compute its points from opposite ends, last bits apart; with a
// tolerance of 1e-12 r each saw the other's point "elsewhere" and the ridge
// had no contact at all. A vertex a float's rounding off its neighbour's edge
// (a T-junction) must not give a second contact beside the face's; a
// zero-area triangle (a common STL defect) gives a NaN closest point, which
// must not count.
TEST_CASE("mesh contacts: a ridge's edge from both sides, a T-junction, a sliver", "[mesh]") {
  std::vector<MeshContact> hits, all;
  TriangleMesh ridge;
  ridge.vertices = {V3(0, 0, 0), V3(16, 0, 0), V3(8, 16, -16), V3(16, 0, 0), V3(0, 0, 0), V3(8, -16, -16)};
  ridge.triangles = {{0, 1, 2}, {3, 4, 5}};
  const MeshWall r(ridge, 0.3);
  for (double x0 : {4.8, 1.3, 7.7, 12.9}) {
    const V3 x(x0, 0, 7.9e-4);
    r.contacts(x, 8e-4, hits);
    r.contacts_all(x, 8e-4, all);
    INFO("x = " << x0);
    REQUIRE(hits.size() == 1);
    REQUIRE(all.size() == 1);
    CHECK(std::abs(hits[0].point.z()) < 1e-15);
  }
  TriangleMesh t;
  const V3 M(0.5, 0.5 + 1e-9, 0);
  t.vertices = {V3(0, 0, 0), V3(1, 1, 0), V3(1, 0, 0), V3(0, 0, 0), M,
                V3(0, 1, 0), M,           V3(1, 1, 0), V3(0, 1, 0)};
  t.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  const MeshWall tj(t, 0.3);
  tj.contacts(V3(0.5005, 0.4995, 0.0099), 0.01, hits);
  tj.contacts_all(V3(0.5005, 0.4995, 0.0099), 0.01, all);
  CHECK(hits.size() == 1);
  CHECK(all.size() == 1);
  TriangleMesh s;
  s.vertices = {V3(-1, -1, 0), V3(1, -1, 0), V3(1, 1, 0), V3(-1, 1, 0),
                V3(0, 0, 0),   V3(0, 0, 0),  V3(1, 1, 0)};
  s.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};
  const MeshWall sliver(s, 0.3);
  sliver.contacts_all(V3(0.5, 0.25, 0.049), 0.05, all);
  REQUIRE(all.size() == 1);
  CHECK(all[0].point.allFinite());
}
