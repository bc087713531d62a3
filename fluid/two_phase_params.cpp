#include "fluid/two_phase_params.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "coflow/config.hpp"
#include "coflow/stl.hpp"
#include "fluid/mesh_voxels.hpp"

namespace coflow::fluid {

namespace {

Vec3 vec(const config::Numbers& n) {
  return {n.values.at(0), n.values.at(1), n.values.at(2)};
}

void need3(config::Visitor& v, const char* key, const config::Numbers& n) {
  if (v.reading() && n.values.size() != 3)
    v.fail(key, fmt::format("needs 3 numbers [x, y, z] (got {})", n.values.size()));
}

void check_box(config::Visitor& v, const config::Numbers& lo, const config::Numbers& hi) {
  if (!v.reading() || lo.values.size() != 3 || hi.values.size() != 3) return;
  for (int d = 0; d < 3; ++d)
    if (hi.values[d] <= lo.values[d])
      v.fail("upper",
             fmt::format("upper[{}] = {} is not above lower[{}] = {}", d, hi.values[d], d, lo.values[d]));
}

// The labels of dataset ds (rank 2 or 3, extents dims) as 0 (fluid) or 1
// (solid, any nonzero label), read plane by plane as 64-bit integers: read
// straight into bytes, HDF5 would clamp a negative label to 0 (fluid).
bool read_labels(hid_t ds, hid_t space, int rank, const hsize_t dims[3], std::vector<std::uint8_t>& out) {
  const hsize_t planes = rank == 3 ? dims[0] : 1, plane = dims[rank - 2] * dims[rank - 1];
  out.resize(static_cast<std::size_t>(planes * plane));
  std::vector<std::int64_t> buf(static_cast<std::size_t>(plane));
  const hid_t mem = H5Screate_simple(1, &plane, nullptr);
  bool ok = true;
  for (hsize_t k = 0; k < planes && ok; ++k) {
    const hsize_t start[3] = {k, 0, 0}, count[3] = {1, dims[rank - 2], dims[rank - 1]};
    const hsize_t* st = rank == 3 ? start : start + 1;
    const hsize_t* ct = rank == 3 ? count : count + 1;
    ok = H5Sselect_hyperslab(space, H5S_SELECT_SET, st, nullptr, ct, nullptr) >= 0 &&
         H5Dread(ds, H5T_NATIVE_INT64, mem, space, H5P_DEFAULT, buf.data()) >= 0;
    for (hsize_t n = 0; ok && n < plane; ++n)
      out[static_cast<std::size_t>(k * plane + n)] = buf[n] != 0 ? 1 : 0;
  }
  H5Sclose(mem);
  return ok;
}

// Reads an HDF5 image into `out` (or only its shape when out is null).
std::string read_hdf5(const SolidParams& s, std::vector<std::uint8_t>* out, std::array<long, 3>& shape) {
  H5E_auto2_t func;
  void* data;
  H5Eget_auto2(H5E_DEFAULT, &func, &data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // report below, not on stderr
  std::string err;
  const hid_t f = H5Fopen(s.file.path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = f >= 0 ? H5Dopen2(f, s.dataset.c_str(), H5P_DEFAULT) : -1;
  if (f < 0)
    err = fmt::format("cannot open {} as HDF5", s.file.path);
  else if (ds < 0)
    err = fmt::format("{} has no dataset '{}'", s.file.path, s.dataset);
  if (ds >= 0) {
    const hid_t sp = H5Dget_space(ds);
    const int rank = H5Sget_simple_extent_ndims(sp);
    hsize_t dims[3] = {1, 1, 1};
    const hid_t type = H5Dget_type(ds);
    const H5T_class_t kind = H5Tget_class(type);
    H5Tclose(type);
    if (kind != H5T_INTEGER) {
      err = fmt::format("dataset '{}' is not of integers: a voxel image is labels (0 fluid, nonzero solid){}",
                        s.dataset,
                        kind == H5T_ENUM ? " (h5py stores a numpy bool array as an enum: write it with "
                                           ".astype('uint8'))"
                                         : "");
    } else if (rank < 2 || rank > 3) {
      err = fmt::format("dataset '{}' has {} dimensions; a voxel image has 2 or 3 ([nz,] ny, nx)", s.dataset,
                        rank);
    } else {
      H5Sget_simple_extent_dims(sp, dims, nullptr);
      shape = {static_cast<long>(dims[rank - 1]), static_cast<long>(dims[rank - 2]),
               rank == 3 ? static_cast<long>(dims[0]) : 1L};
      if (out && !read_labels(ds, sp, rank, dims, *out))
        err = fmt::format("cannot read dataset '{}' of {} as integers", s.dataset, s.file.path);
    }
    H5Sclose(sp);
    H5Dclose(ds);
  }
  if (f >= 0) H5Fclose(f);
  H5Eset_auto2(H5E_DEFAULT, func, data);
  return err;
}

// Reads a voxel image; "" or what is wrong.
std::string read_voxels(const SolidParams& s, std::vector<std::uint8_t>* out) {
  if (const std::string why = config::file_problem(s.file.path); !why.empty())
    return fmt::format("{}: {}", s.file.path, why);
  if (!std::filesystem::is_regular_file(s.file.path))  // a pipe: an image is read by its size
    return fmt::format("{}: not a regular file", s.file.path);
  std::array<long, 3> want{}, got{};
  for (int d = 0; d < 3; ++d) want[d] = std::lround(s.shape.values.at(d));
  if (!s.dataset.empty()) {
    if (auto err = read_hdf5(s, out, got); !err.empty()) return err;
    if (got != want)
      return fmt::format("dataset '{}' is {} x {} x {} voxels (x, y, z), not the shape {} x {} x {}",
                         s.dataset, got[0], got[1], got[2], want[0], want[1], want[2]);
    return "";
  }
  const auto bytes = static_cast<long>(std::filesystem::file_size(s.file.path));
  if (bytes != want[0] * want[1] * want[2])
    return fmt::format(
        "the raw image holds {} bytes, but shape {} x {} x {} needs {} (one uint8 per voxel, x "
        "fastest; or give dataset for HDF5): {}",
        bytes, want[0], want[1], want[2], want[0] * want[1] * want[2], s.file.path);
  if (out) {
    out->resize(static_cast<std::size_t>(bytes));
    std::ifstream in(s.file.path, std::ios::binary);
    if (!in.read(reinterpret_cast<char*>(out->data()), bytes))
      return fmt::format("cannot read {}", s.file.path);
  }
  return "";
}

// The keys of a sphere (centre, radius) or a box (lower, upper); `between`
// reads what the item adds (phase, contact angle) before the shape's checks.
// A shape whose bounding box [lo, hi] misses the domain covers no cell.
void check_overlap(config::Visitor& s, const config::Config& cfg, const char* key, const Vec3& lo, const Vec3& hi) {
  const auto& d = cfg.domain;
  for (int a = 0; a < 3; ++a)
    if (hi[a] < d.lower[a] || lo[a] > d.upper[a]) {
      s.fail(key, fmt::format("it lies outside the domain along {} ([{}, {}] m against the domain's [{}, {}] m): "
                              "check its coordinates{}",
                              "xyz"[a], lo[a], hi[a], d.lower[a], d.upper[a],
                              std::string(key) == "file" ? ", scale and translate" : ""));
      return;
    }
}

template <class Between>
void visit_sphere(config::Visitor& s, const config::Config& cfg, Shape& r, Between between) {
  r.kind = "sphere";
  r.planar = s.reading() && cfg.domain.cells[2] == 1;
  s.required("centre", r.centre, "[x, y, z], m");
  s.required("radius", r.radius, "m", config::positive());
  between();
  need3(s, "centre", r.centre);
  if (!s.reading() || r.centre.values.size() != 3) return;
  const Vec3 c = vec(r.centre);
  check_overlap(s, cfg, "centre", {c[0] - r.radius, c[1] - r.radius, r.planar ? cfg.domain.lower[2] : c[2] - r.radius},
                {c[0] + r.radius, c[1] + r.radius, r.planar ? cfg.domain.upper[2] : c[2] + r.radius});
}

template <class Between>
void visit_box(config::Visitor& s, const config::Config& cfg, Shape& r, Between between) {
  r.kind = "box";
  s.required("lower", r.lower, "[x, y, z], m");
  s.required("upper", r.upper, "[x, y, z], m");
  between();
  need3(s, "lower", r.lower);
  need3(s, "upper", r.upper);
  check_box(s, r.lower, r.upper);
  if (s.reading() && r.lower.values.size() == 3 && r.upper.values.size() == 3)
    check_overlap(s, cfg, "lower", vec(r.lower), vec(r.upper));
}

}  // namespace

void TwoPhaseParams::visit(config::Visitor& v) {
  v.required("surface_tension", surface_tension, "interfacial tension between the two fluids, N/m",
             config::non_negative());
  v("beta", beta,
    "recolouring strength (Latva-Kokko & Rothman 2005): how sharply the colours separate; the interface is a "
    "few "
    "cells wide at 0.7",
    config::Rule{"in (0, 1]", [](const config::ValueRef& r) {
                   const double x = *std::get<double*>(r);
                   return x > 0.0 && x <= 1.0 ? std::string() : fmt::format("must be in (0, 1] (got {})", x);
                 }});
  v("viscosity_blue", viscosity_blue,
    "kinematic viscosity of the blue fluid, m^2/s (default: fluid.viscosity, that of the red fluid)",
    config::non_negative());
  v("contact_angle", contact_angle,
    "degrees, measured in the red fluid: of the box's walls, and of solids that do not give their own",
    config::in_range(0.0, 180.0));
  v("wetting", wetting,
    "geometric: at fluid cells next to a solid the colour gradient is turned to meet the solid at the "
    "contact "
    "angle (Leclaire et al. 2017, Akai et al. 2018); seed: a solid takes the fixed colour cos(contact_angle) "
    "in "
    "its neighbours' colour gradient (Latva-Kokko & Rothman 2005), which misses the angle by up to 14 "
    "degrees "
    "(docs/validation.md)",
    config::one_of({"geometric", "seed"}));
  v("colour_field", colour_field,
    "the field whose gradient is the colour gradient: difference, rho_r - rho_b (seed 000 eq. 2.56); phase, "
    "(rho_r - rho_b) / (rho_r + rho_b), whose gradient is zero in a region of one colour where the density "
    "varies (a pressure drop), so that the interfacial perturbation acts at interfaces only "
    "(docs/validation.md)",
    config::one_of({"difference", "phase"}));
}

bool Shape::contains(const Vec3& x) const {
  if (kind == "fill") return true;
  if (kind == "sphere") {
    const Vec3 c = vec(centre);
    return std::hypot(x[0] - c[0], x[1] - c[1], planar ? 0.0 : x[2] - c[2]) <= radius;
  }
  for (int d = 0; d < 3; ++d)
    if (x[d] < lower.values.at(d) || x[d] > upper.values.at(d)) return false;
  return true;
}

double painted_phase(const std::vector<PhaseRegion>& regions, const Vec3& x) {
  double phase = 1.0;  // red where nothing is painted
  for (const auto& r : regions)
    if (r.contains(x)) phase = r.phase == "red" ? 1.0 : -1.0;
  return phase;
}

void visit_phase_regions(config::Visitor& v, const config::Config& cfg, std::vector<PhaseRegion>& out) {
  const auto phase = [](config::Visitor& s, PhaseRegion& r) {
    s.required("phase", r.phase, "the fluid painted: red (that of fluid.viscosity) or blue",
               config::one_of({"red", "blue"}));
  };
  v.choices(
      "phase",
      "two-phase: the initial fluids, painted in order (the last region that holds a cell's centre wins; red "
      "where none does)",
      {{"fill", "the whole domain", [&, phase](config::Visitor& s) { phase(s, out.emplace_back()); }},
       {"sphere", "a sphere (a disc in 2D: z is ignored)",
        [&, phase](config::Visitor& s) {
          auto& r = out.emplace_back();
          visit_sphere(s, cfg, r, [&] { phase(s, r); });
        }},
       {"box", "an axis-aligned box", [&, phase](config::Visitor& s) {
          auto& r = out.emplace_back();
          visit_box(s, cfg, r, [&] { phase(s, r); });
        }}});
}

void visit_solids(config::Visitor& v, const config::Config& cfg, std::vector<SolidParams>& out) {
  const auto angle = [](config::Visitor& s, SolidParams& p) {
    s("contact_angle", p.contact_angle,
      "two-phase: degrees, in the red fluid; -1: fluid.two_phase.contact_angle",
      config::Rule{"in [0, 180] or -1", [](const config::ValueRef& r) {
                     const double x = *std::get<double*>(r);
                     return x == -1.0 || (x >= 0.0 && x <= 180.0)
                                ? std::string()
                                : fmt::format(
                                      "must be in [0, 180] degrees, or -1 for fluid.two_phase.contact_angle "
                                      "(got {})",
                                      x);
                   }});
  };
  v.choices(
      "solids",
      "interior solids of the fluid (half-way bounce-back at the faces of solid cells, or where the links "
      "cross "
      "the solid's surface with fluid.lbm.bounce_back: interpolated or central): a cell is solid when its "
      "centre is "
      "inside "
      "one; a later item's contact angle wins where they overlap",
      {{"voxels", "an image on the fluid grid, one voxel per cell, nonzero = solid",
        [&, angle](config::Visitor& s) {
          auto& p = out.emplace_back();
          p.kind = "voxels";
          s.required("file", p.file, "raw uint8 (x fastest, no header) or HDF5 (give dataset)");
          s("dataset", p.dataset, "HDF5: the dataset, integers of shape [nz, ny, nx] (C order: x fastest)");
          s.required("shape", p.shape, "[nx, ny, nz] voxels: must equal domain.cells");
          angle(s, p);
          if (!s.reading()) return;
          need3(s, "shape", p.shape);
          if (p.shape.values.size() != 3) return;
          for (int d = 0; d < 3; ++d)
            if (std::lround(p.shape.values[d]) != cfg.domain.cells[d]) {
              s.fail("shape",
                     fmt::format("shape [{}, {}, {}] differs from domain.cells [{}, {}, {}]: the image "
                                 "maps one voxel to one cell",
                                 p.shape.values[0], p.shape.values[1], p.shape.values[2], cfg.domain.cells[0],
                                 cfg.domain.cells[1], cfg.domain.cells[2]));
              return;
            }
          if (auto err = check_voxel_file(p); !err.empty()) s.fail("file", err);
        }},
       {"mesh", "a closed triangle mesh (STL, ASCII or binary): the cells whose centres it holds",
        [&, angle](config::Visitor& s) {
          auto& p = out.emplace_back();
          p.kind = "mesh";
          s.required("file", p.file, "an STL file, relative to this file");
          s("scale", p.scale,
            "factor applied to the file's coordinates (0.001 for a mesh drawn in millimetres)",
            config::positive());
          s("translate", p.translate, "shift in m applied after the scale");
          angle(s, p);
          if (!s.reading()) return;
          try {
            const stl::MeshSummary m = stl::summarize(load_solid_mesh(p));
            if (!m.closed)
              s.fail("file",
                     fmt::format("{}: the mesh is open ({} edges of one triangle); a solid needs a closed "
                                 "surface, whose inside is the solid",
                                 p.file.path, m.open_edges));
            check_overlap(s, cfg, "file", {m.lower[0], m.lower[1], m.lower[2]}, {m.upper[0], m.upper[1], m.upper[2]});
          } catch (const std::runtime_error& e) {
            s.fail("file", e.what());
          }
        }},
       {"sphere", "a sphere (a disc in 2D: z is ignored)",
        [&, angle](config::Visitor& s) {
          auto& p = out.emplace_back();
          visit_sphere(s, cfg, p, [&] { angle(s, p); });
        }},
       {"box", "an axis-aligned box", [&, angle](config::Visitor& s) {
          auto& p = out.emplace_back();
          visit_box(s, cfg, p, [&] { angle(s, p); });
        }}});
}

std::string check_voxel_file(const SolidParams& s) {
  return read_voxels(s, nullptr);
}

stl::TriangleMesh load_solid_mesh(const SolidParams& s) {
  stl::TriangleMesh m = stl::read(s.file.path);
  stl::transform(m, s.scale, stl::V3(s.translate[0], s.translate[1], s.translate[2]));
  return m;
}

std::vector<std::uint8_t> solid_map(const config::Config& cfg, const std::vector<SolidParams>& solids) {
  const auto& d = cfg.domain;
  const auto h = d.spacing();
  const long nx = d.cells[0], ny = d.cells[1], nz = d.cells[2];
  std::vector<std::uint8_t> map(static_cast<std::size_t>(nx * ny * nz), 0);
  if (solids.size() > 254) throw std::runtime_error("fluid.solids: at most 254 solids");
  for (std::size_t n = 0; n < solids.size(); ++n) {
    const auto& s = solids[n];
    const auto id = static_cast<std::uint8_t>(n + 1);
    if (s.kind == "mesh") {
      const auto inside = mesh_voxels(load_solid_mesh(s), cfg.domain);
      for (std::size_t c = 0; c < map.size(); ++c)
        if (inside[c]) map[c] = id;
      continue;
    }
    if (s.kind == "voxels") {
      std::vector<std::uint8_t> img;
      if (auto err = read_voxels(s, &img); !err.empty()) throw std::runtime_error("fluid.solids: " + err);
      for (std::size_t c = 0; c < map.size(); ++c)
        if (img[c] != 0) map[c] = id;
      continue;
    }
    std::size_t c = 0;
    for (long k = 0; k < nz; ++k)
      for (long j = 0; j < ny; ++j)
        for (long i = 0; i < nx; ++i, ++c)
          if (s.contains({d.lower[0] + (i + 0.5) * h[0], d.lower[1] + (j + 0.5) * h[1],
                          d.lower[2] + (k + 0.5) * h[2]}))
            map[c] = id;
  }
  return map;
}

}  // namespace coflow::fluid
