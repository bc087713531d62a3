// fluid.solids: a voxel image read from raw bytes and from HDF5 gives the same
// solid map, cell for cell (x fastest, HDF5 in [nz][ny][nx] order); a sphere
// covers the cells whose centres it holds; a missing dataset is an error
// naming it. STL meshes: a cube on cell faces gives the box's cells exactly, a
// finely tessellated sphere the sphere's cells but for a few at its surface,
// and an open mesh is refused.
#include <fmt/format.h>
#include <hdf5.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "coflow/catalog.hpp"
#include "coflow/run_config.hpp"
#include "fluid/params.hpp"
#include "fluid/solid_surface.hpp"
#include "tests/unit/worst.hpp"

using namespace coflow;

namespace {

const long nx = 6, ny = 5, nz = 4;

std::vector<std::uint8_t> pattern() {
  std::vector<std::uint8_t> v(nx * ny * nz);
  for (long k = 0; k < nz; ++k)
    for (long j = 0; j < ny; ++j)
      for (long i = 0; i < nx; ++i) v[(k * ny + j) * nx + i] = (i + 2 * j + 3 * k) % 4 == 0 ? 7 : 0;
  return v;
}

// The 6 x 5 x 4 mm box of 1 mm cells (z_cells: fewer along z, 1 mm each).
config::Config config_of(const std::string& solids_yaml, long z_cells = nz) {
  const std::string text = fmt::format(
      "run: {{name: t, end_time: 1.0}}\n"
      "domain: {{lower: [0, 0, 0], upper: [0.006, 0.005, {}], cells: [{}, {}, {}], periodic: [true, true, "
      "true]}}\n"
      "fluid: {{solver: lbm, density: 1000.0, viscosity: 1.0e-6, solids: {}}}\n",
      0.001 * z_cells, nx, ny, z_cells, solids_yaml);
  return config::parse_config_node(YAML::Load(text), "t.yaml", coflow::catalog());
}

fluid::FluidParams fluid_of(const config::Config& cfg) {
  fluid::FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);
  return p;
}

std::vector<std::uint8_t> solids_of(const std::string& solids_yaml) {
  const config::Config cfg = config_of(solids_yaml);
  return fluid::solid_map(cfg, fluid_of(cfg).solids);
}

// The solids' map and their surface as the interpolated bounce-back sees it.
struct Surface {
  config::Config cfg;
  std::vector<std::uint8_t> map;
  std::unique_ptr<fluid::SolidSurface> surface;
  explicit Surface(const std::string& solids_yaml, long z_cells = nz) : cfg(config_of(solids_yaml, z_cells)) {
    const auto p = fluid_of(cfg);
    map = fluid::solid_map(cfg, p.solids);
    surface = std::make_unique<fluid::SolidSurface>(cfg, p.solids);
  }
  int id(long i, long j, long k) const {
    const auto w = [](long a, long n) { return (a % n + n) % n; };  // the box is periodic
    return map[static_cast<std::size_t>((w(k, nz) * ny + w(j, ny)) * nx + w(i, nx))];
  }
  // Calls f(cell, e, fraction) for every link from a fluid cell into a solid
  // one within the box (the wrap across periodic faces is checked apart).
  template <class F>
  void links(F&& f) const {
    for (long k = 0; k < nz; ++k)
      for (long j = 0; j < ny; ++j)
        for (long i = 0; i < nx; ++i)
          for (int a = -1; a <= 1; ++a)
            for (int b = -1; b <= 1; ++b)
              for (int c = -1; c <= 1; ++c) {
                const int e[3] = {a, b, c}, id_to = id(i + a, j + b, k + c);
                const bool inside =
                    i + a >= 0 && i + a < nx && j + b >= 0 && j + b < ny && k + c >= 0 && k + c < nz;
                if (!inside || id(i, j, k) || !id_to || std::abs(a) + std::abs(b) + std::abs(c) == 3)
                  continue;
                f(std::array<long, 3>{i, j, k}, e, surface->fraction({i, j, k}, e, id_to));
              }
  }
};

}  // namespace

TEST_CASE("solids: raw and HDF5 voxel images, spheres", "[fluid][solids]") {
  const auto dir = std::filesystem::temp_directory_path() / ("coflow-solids-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string raw = (dir / "img.raw").string(), h5 = (dir / "img.h5").string();
  const auto img = pattern();
  std::ofstream(raw, std::ios::binary).write(reinterpret_cast<const char*>(img.data()), img.size());
  {
    const hid_t f = H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t dims[3] = {nz, ny, nx};
    const hid_t sp = H5Screate_simple(3, dims, nullptr);
    const hid_t ds = H5Dcreate2(f, "rock", H5T_NATIVE_UINT8, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds, H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, img.data());
    H5Dclose(ds);
    // The same solids labelled -1 and 300 in 16-bit integers: read straight
    // into bytes, HDF5 clamped -1 to 0 (fluid) and 300 to 255.
    std::vector<std::int16_t> signed_labels(img.size());
    for (std::size_t c = 0; c < img.size(); ++c) signed_labels[c] = img[c] ? (c % 2 ? -1 : 300) : 0;
    const hid_t ds16 = H5Dcreate2(f, "signed", H5T_NATIVE_INT16, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(ds16, H5T_NATIVE_INT16, H5S_ALL, H5S_ALL, H5P_DEFAULT, signed_labels.data());
    H5Dclose(ds16);
    H5Sclose(sp);
    H5Fclose(f);
  }
  const auto from_raw =
      solids_of(fmt::format("[{{voxels: {{file: {}, shape: [{}, {}, {}]}}}}]", raw, nx, ny, nz));
  const auto from_h5 = solids_of(
      fmt::format("[{{voxels: {{file: {}, dataset: rock, shape: [{}, {}, {}]}}}}]", h5, nx, ny, nz));
  REQUIRE(from_raw.size() == img.size());
  long solid = 0;
  for (std::size_t c = 0; c < img.size(); ++c) {
    CHECK(from_raw[c] == (img[c] ? 1 : 0));  // solid id 1: the first item
    solid += img[c] ? 1 : 0;
  }
  CHECK(solid > 0);
  CHECK(from_h5 == from_raw);
  CHECK(solids_of(fmt::format("[{{voxels: {{file: {}, dataset: signed, shape: [{}, {}, {}]}}}}]", h5, nx, ny,
                              nz)) == from_raw);

  // A sphere of radius 1.5 mm at a cell corner holds the 8 centres around it
  // (at sqrt(3)/2 mm) and the 24 at sqrt(11)/2 mm = 1.66 mm are outside; the
  // later item wins where they overlap (id 2).
  const auto sphere =
      solids_of(fmt::format("[{{voxels: {{file: {}, shape: [{}, {}, {}]}}}}, {{sphere: {{centre: [0.003, "
                            "0.002, 0.002], radius: 0.0015}}}}]",
                            raw, nx, ny, nz));
  long twos = 0;
  for (auto v : sphere) twos += v == 2 ? 1 : 0;
  CHECK(twos == 8);

  CHECK_THROWS_WITH(solids_of(fmt::format("[{{voxels: {{file: {}, dataset: nope, shape: [{}, {}, {}]}}}}]",
                                          h5, nx, ny, nz)),
                    Catch::Contains("no dataset 'nope'"));
  std::filesystem::remove_all(dir);
}

namespace {

void write_stl(const std::string& path, const std::vector<std::array<std::array<double, 3>, 3>>& tris) {
  std::ofstream out(path);
  out << "solid t\n";
  for (const auto& t : tris) {
    out << "facet normal 0 0 0\nouter loop\n";
    for (const auto& v : t) out << fmt::format("vertex {:.17g} {:.17g} {:.17g}\n", v[0], v[1], v[2]);
    out << "endloop\nendfacet\n";
  }
  out << "endsolid t\n";
}

// A UV sphere of radius r about c: n rings, 2 n segments, closed.
std::vector<std::array<std::array<double, 3>, 3>> uv_sphere(std::array<double, 3> c, double r, int n) {
  const auto at = [&](int i, int j) {
    const double th = std::numbers::pi * i / n, ph = std::numbers::pi * j / n;
    const double s = i == 0 || i == n ? 0.0 : std::sin(th);
    return std::array<double, 3>{c[0] + r * s * std::cos(ph), c[1] + r * s * std::sin(ph),
                                 c[2] + r * (i == 0   ? 1.0
                                             : i == n ? -1.0
                                                      : std::cos(th))};
  };
  std::vector<std::array<std::array<double, 3>, 3>> t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const int k = (j + 1) % (2 * n);
      if (i > 0) t.push_back({at(i, j), at(i + 1, j), at(i, k)});
      if (i < n - 1) t.push_back({at(i, k), at(i + 1, j), at(i + 1, k)});
    }
  return t;
}

// The box [lo, hi] as 12 triangles, wound outwards.
std::vector<std::array<std::array<double, 3>, 3>> box_triangles(const double lo[3], const double hi[3]) {
  std::vector<std::array<std::array<double, 3>, 3>> t;
  const auto v = [&](int m) {
    return std::array<double, 3>{m & 1 ? hi[0] : lo[0], m & 2 ? hi[1] : lo[1], m & 4 ? hi[2] : lo[2]};
  };
  for (const auto& q : std::vector<std::array<int, 4>>{
           {0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}}) {
    t.push_back({v(q[0]), v(q[1]), v(q[2])});
    t.push_back({v(q[0]), v(q[2]), v(q[3])});
  }
  return t;
}

}  // namespace

TEST_CASE("solids: STL meshes voxelised", "[fluid][solids]") {
  const auto dir = std::filesystem::temp_directory_path() / ("coflow-mesh-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string cube = (dir / "cube.stl").string(), ball = (dir / "ball.stl").string();
  const std::string open = (dir / "open.stl").string();
  // The cube [1, 4] x [2, 4] x [1, 3] mm (cell faces), 12 triangles.
  const double lo[3] = {0.001, 0.002, 0.001}, hi[3] = {0.004, 0.004, 0.003};
  auto t = box_triangles(lo, hi);
  write_stl(cube, t);
  const auto from_mesh = solids_of(fmt::format("[{{mesh: {{file: {}}}}}]", cube));
  const auto from_box = solids_of("[{box: {lower: [0.001, 0.002, 0.001], upper: [0.004, 0.004, 0.003]}}]");
  CHECK(from_mesh == from_box);
  long n = 0;
  for (auto c : from_box) n += c;
  CHECK(n == 3 * 2 * 2);
  t.pop_back();  // one triangle less: open
  write_stl(open, t);
  CHECK_THROWS_WITH(solids_of(fmt::format("[{{mesh: {{file: {}}}}}]", open)),
                    Catch::Contains("the mesh is open"));
  // A sphere of radius 2 mm from 16 128 triangles, in millimetres (scale
  // 0.001), against the analytic sphere.
  write_stl(ball, uv_sphere({3.0, 2.5, 2.0}, 2.0, 64));
  const auto mesh_ball = solids_of(fmt::format("[{{mesh: {{file: {}, scale: 0.001}}}}]", ball));
  const auto true_ball = solids_of("[{sphere: {centre: [0.003, 0.0025, 0.002], radius: 0.002}}]");
  long both = 0, either = 0;
  for (std::size_t c = 0; c < true_ball.size(); ++c) {
    both += mesh_ball[c] && true_ball[c];
    either += mesh_ball[c] || true_ball[c];
  }
  CHECK(both > 0);
  CHECK(both == either);
  std::filesystem::remove_all(dir);
}

// Where the links of D3Q19 from fluid cells into solids cross their surfaces
// (fluid.lbm.bounce_back: interpolated; Bouzidi, Firdaouss & Lallemand 2001's
// q): against the exact crossings of a box's planes and a sphere's, a mesh of
// the same box and of the sphere against them, voxels at the half, and across
// a periodic face at the solid cell's image.
TEST_CASE("solids: where the lattice links enter them", "[fluid][solids]") {
  // The box [1.3, 4.7] x [2.2, 3.6] x [1.1, 2.8] mm: a link crosses the plane
  // it meets first, e.g. from the centre x = 0.5 mm towards +x at 0.8 of a cell.
  const double lo[3] = {0.0013, 0.0022, 0.0011}, hi[3] = {0.0047, 0.0036, 0.0028};
  const Surface box(fmt::format("[{{box: {{lower: [{}, {}, {}], upper: [{}, {}, {}]}}}}]", lo[0], lo[1],
                                lo[2], hi[0], hi[1], hi[2]));
  long n = 0;
  box.links([&](const std::array<long, 3>& c, const int* e, double q) {
    double t = 0.0;  // the slabs' entry: the latest of the axes' entries
    for (int d = 0; d < 3; ++d) {
      const double x = (c[d] + 0.5) * 1e-3;
      if (e[d] > 0 && x < lo[d]) t = std::max(t, (lo[d] - x) / 1e-3);
      if (e[d] < 0 && x > hi[d]) t = std::max(t, (x - hi[d]) / 1e-3);
    }
    CHECK(q == Approx(t).margin(1e-12));
    CHECK(q > 0.0);
    CHECK(q <= 1.0);
    ++n;
  });
  CHECK(n > 50);

  // A sphere of radius 1.7 mm: along an axis the crossing of a circle of
  // radius sqrt(r^2 - s^2) (s the link's distance from the centre).
  const std::array<double, 3> centre{0.0031, 0.0024, 0.0019};
  const double r = 0.0017;
  const Surface ball(
      fmt::format("[{{sphere: {{centre: [{}, {}, {}], radius: {}}}}}]", centre[0], centre[1], centre[2], r));
  long axial = 0;
  ball.links([&](const std::array<long, 3>& c, const int* e, double q) {
    int axis = -1, count = 0;
    for (int d = 0; d < 3; ++d)
      if (e[d] != 0) axis = d, ++count;
    if (count != 1) return;
    double s2 = 0.0;
    for (int d = 0; d < 3; ++d)
      if (d != axis) s2 += std::pow((c[d] + 0.5) * 1e-3 - centre[d], 2);
    const double x = (c[axis] + 0.5) * 1e-3, half = std::sqrt(r * r - s2);
    const double wall = e[axis] > 0 ? centre[axis] - half : centre[axis] + half;
    CHECK(q == Approx(std::abs(wall - x) / 1e-3).margin(1e-12));
    ++axial;
  });
  CHECK(axial > 20);

  // The same box and sphere as STL meshes: the box's crossings to round-off,
  // the sphere's within its 16 128 triangles' sagitta, r (1 - cos(pi / 64)) =
  // 2.0e-3 mm, against the analytic sphere's (links that both maps share).
  const auto dir = std::filesystem::temp_directory_path() / ("coflow-links-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  write_stl((dir / "box.stl").string(), box_triangles(lo, hi));
  write_stl((dir / "ball.stl").string(), uv_sphere({3.1, 2.4, 1.9}, 1.7, 64));
  const Surface box_mesh(fmt::format("[{{mesh: {{file: {}}}}}]", (dir / "box.stl").string()));
  const Surface ball_mesh(fmt::format("[{{mesh: {{file: {}, scale: 0.001}}}}]", (dir / "ball.stl").string()));
  CHECK(box_mesh.map == box.map);
  double worst_box = 0.0, worst_ball = 0.0;
  long m = 0;
  box_mesh.links([&](const std::array<long, 3>& c, const int* e, double q) {
    worst_box = coflow::test::worst_of(worst_box, std::abs(q - box.surface->fraction(c, e, 1)));
  });
  ball_mesh.links([&](const std::array<long, 3>& c, const int* e, double q) {
    if (!ball.id(c[0] + e[0], c[1] + e[1], c[2] + e[2]) || ball.id(c[0], c[1], c[2])) return;
    worst_ball = coflow::test::worst_of(worst_ball, std::abs(q - ball.surface->fraction(c, e, 1)));
    ++m;
  });
  CHECK(worst_box < 1e-12);
  CHECK(m > 50);
  CHECK(worst_ball < 2.5e-3);
  CHECK(worst_ball > 0.0);  // a mesh, not the sphere

  // A voxel image: its voxels' faces, half-way.
  const std::string raw = (dir / "img.raw").string();
  const auto img = pattern();
  std::ofstream(raw, std::ios::binary).write(reinterpret_cast<const char*>(img.data()), img.size());
  const Surface voxels(fmt::format("[{{voxels: {{file: {}, shape: [{}, {}, {}]}}}}]", raw, nx, ny, nz));
  long halves = 0;
  voxels.links([&](const std::array<long, 3>&, const int*, double q) { halves += q == 0.5 ? 1 : -1000; });
  CHECK(halves > 0);

  // Across the periodic x face: the link from cell 0 towards -x ends in cell
  // 5, whose centre (5.5 mm) a sphere of 0.8 mm holds: its surface at 6.3 mm
  // of the image's 6.5 (cell 0's centre moved by the period), 0.2 of the link.
  const Surface wrap("[{sphere: {centre: [0.0055, 0.0025, 0.0015], radius: 0.0008}}]");
  const int minus_x[3] = {-1, 0, 0};
  REQUIRE(wrap.id(5, 2, 1) == 1);
  CHECK(wrap.surface->fraction({0, 2, 1}, minus_x, 1) == Approx(0.2).margin(1e-12));

  // One cell along z (D3Q19 on a periodic slab): a link (1, 0, +-1) streams
  // to the cell at +x, so it crosses the box's face x = 1.7 mm where (1, 0,
  // 0) does, at 0.2 of the link from the centre 1.5 mm (not at the slab's
  // faces, 0.5 of a link away along z).
  const Surface slab("[{box: {lower: [0.0017, 0.0, 0.0], upper: [0.0045, 0.005, 0.001]}}]", 1);
  const int plus_x[3] = {1, 0, 0}, plus_xz[3] = {1, 0, 1}, plus_x_minus_z[3] = {1, 0, -1};
  CHECK(slab.surface->fraction({1, 2, 0}, plus_x, 1) == Approx(0.2).margin(1e-12));
  CHECK(slab.surface->fraction({1, 2, 0}, plus_xz, 1) == Approx(0.2).margin(1e-12));
  CHECK(slab.surface->fraction({1, 2, 0}, plus_x_minus_z, 1) == Approx(0.2).margin(1e-12));
  std::filesystem::remove_all(dir);
}
