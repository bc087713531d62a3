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
#include <numbers>
#include <string>
#include <vector>

#include "coflow/catalog.hpp"
#include "coflow/run_config.hpp"
#include "fluid/params.hpp"

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

std::vector<std::uint8_t> solids_of(const std::string& solids_yaml) {
  const std::string text = fmt::format(
      "run: {{name: t, end_time: 1.0}}\n"
      "domain: {{lower: [0, 0, 0], upper: [0.006, 0.005, 0.004], cells: [{}, {}, {}], periodic: [true, true, "
      "true]}}\n"
      "fluid: {{solver: lbm, density: 1000.0, viscosity: 1.0e-6, solids: {}}}\n",
      nx, ny, nz, solids_yaml);
  const config::Config cfg = config::parse_config_node(YAML::Load(text), "t.yaml", coflow::catalog());
  fluid::FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);
  return fluid::solid_map(cfg, p.solids);
}

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

}  // namespace

TEST_CASE("solids: STL meshes voxelised", "[fluid][solids]") {
  const auto dir = std::filesystem::temp_directory_path() / ("coflow-mesh-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string cube = (dir / "cube.stl").string(), ball = (dir / "ball.stl").string();
  const std::string open = (dir / "open.stl").string();
  // The cube [1, 4] x [2, 4] x [1, 3] mm (cell faces), 12 triangles.
  const double lo[3] = {0.001, 0.002, 0.001}, hi[3] = {0.004, 0.004, 0.003};
  std::vector<std::array<std::array<double, 3>, 3>> t;
  const auto v = [&](int m) {
    return std::array<double, 3>{m & 1 ? hi[0] : lo[0], m & 2 ? hi[1] : lo[1], m & 4 ? hi[2] : lo[2]};
  };
  for (const auto& q : std::vector<std::array<int, 4>>{
           {0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}}) {
    t.push_back({v(q[0]), v(q[1]), v(q[2])});
    t.push_back({v(q[0]), v(q[2]), v(q[3])});
  }
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
  // A sphere of radius 2 mm from 8192 triangles, in millimetres (scale
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
