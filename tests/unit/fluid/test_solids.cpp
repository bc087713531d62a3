// fluid.solids: a voxel image read from raw bytes and from HDF5 gives the same
// solid map, cell for cell (x fastest, HDF5 in [nz][ny][nx] order); a sphere
// covers the cells whose centres it holds; a missing dataset or a wrong size
// is an error naming what is wrong.
#include <hdf5.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

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
      "domain: {{lower: [0, 0, 0], upper: [0.006, 0.005, 0.004], cells: [{}, {}, {}], periodic: [true, true, true]}}\n"
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
    H5Sclose(sp);
    H5Fclose(f);
  }
  const auto from_raw = solids_of(fmt::format("[{{voxels: {{file: {}, shape: [{}, {}, {}]}}}}]", raw, nx, ny, nz));
  const auto from_h5 =
      solids_of(fmt::format("[{{voxels: {{file: {}, dataset: rock, shape: [{}, {}, {}]}}}}]", h5, nx, ny, nz));
  REQUIRE(from_raw.size() == img.size());
  long solid = 0;
  for (std::size_t c = 0; c < img.size(); ++c) {
    CHECK(from_raw[c] == (img[c] ? 1 : 0));  // solid id 1: the first item
    solid += img[c] ? 1 : 0;
  }
  CHECK(solid > 0);
  CHECK(from_h5 == from_raw);

  // A sphere of radius 1.5 mm at a cell corner holds the 8 centres around it
  // (at sqrt(3)/2 mm) and the 24 at sqrt(11)/2 mm = 1.66 mm are outside; the
  // later item wins where they overlap (id 2).
  const auto sphere = solids_of(fmt::format(
      "[{{voxels: {{file: {}, shape: [{}, {}, {}]}}}}, {{sphere: {{centre: [0.003, 0.002, 0.002], radius: 0.0015}}}}]",
      raw, nx, ny, nz));
  long twos = 0;
  for (auto v : sphere) twos += v == 2 ? 1 : 0;
  CHECK(twos == 8);

  CHECK_THROWS_WITH(solids_of(fmt::format("[{{voxels: {{file: {}, dataset: nope, shape: [{}, {}, {}]}}}}]", h5, nx,
                                          ny, nz)),
                    Catch::Contains("no dataset 'nope'"));
  std::filesystem::remove_all(dir);
}
