// The fluid keys of two-phase flow and of interior solids, common to the
// variants that take them (lbm, lbm-reference): fluid.two_phase,
// fluid.initial.phase (painted regions) and fluid.solids (voxel images,
// spheres, boxes). Part of the fluid schema library.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "coflow/config.hpp"
#include "coflow/run_config.hpp"
#include "coflow/stl.hpp"

namespace coflow::fluid {

using config::Vec3;

// fluid.two_phase: the colour-gradient model of seed 000 §2.3.4. The fluid of
// fluid.density and fluid.viscosity is "red", the other "blue"; both have the
// same density (the seed's model).
struct TwoPhaseParams {
  bool on = false;                    // the section is given
  double surface_tension = 0.0;       // N/m
  double beta = 0.7;                  // recolouring (Latva-Kokko & Rothman 2005)
  double viscosity_blue = 0.0;        // m^2/s (0: fluid.viscosity)
  double contact_angle = 90.0;        // degrees, measured in the red fluid, on the box walls
  std::string wetting = "geometric";  // geometric (Leclaire et al. 2017) | seed (solid colour cos(theta))
  std::string colour_field = "difference";  // the field of the colour gradient: rho_r - rho_b (seed) | phase
  void visit(config::Visitor& v);
};

// A sphere or an axis-aligned box (or, for a painted region, everything).
struct Shape {
  std::string kind;  // fill | sphere | box (and the solids' voxels | mesh)
  config::Numbers centre, lower, upper;
  double radius = 0.0;
  bool planar = false;                 // a 2D run: a sphere is a disc (z ignored)
  bool contains(const Vec3& x) const;  // fill, sphere, box
};

// One painted region of fluid.initial.phase: fill (everything), sphere or box.
struct PhaseRegion : Shape {
  std::string phase = "red";  // red | blue
  PhaseRegion() { kind = "fill"; }
};

// One interior solid of fluid.solids: a voxel image, a closed STL mesh, a
// sphere or a box.
struct SolidParams : Shape {
  SolidParams() { kind = "voxels"; }
  config::FilePath file;        // voxels: raw uint8 (x fastest) or HDF5; mesh: STL
  double scale = 1.0;           // mesh: factor on the file's coordinates
  Vec3 translate{0, 0, 0};      // mesh: shift after the scale, m
  std::string dataset;          // voxels in HDF5: the dataset's name
  config::Numbers shape;        // voxels: [nx, ny, nz], = domain.cells
  double contact_angle = -1.0;  // degrees; -1: fluid.two_phase.contact_angle
};

// The phase (+1 red, -1 blue) painted at x: the last region that holds x.
double painted_phase(const std::vector<PhaseRegion>& regions, const Vec3& x);

// Read the list keys (under fluid:) into their vectors.
void visit_phase_regions(config::Visitor& v, const config::Config& cfg, std::vector<PhaseRegion>& out);
void visit_solids(config::Visitor& v, const config::Config& cfg, std::vector<SolidParams>& out);

// The interior solids on the global grid: per cell (x fastest) 0 for fluid or
// 1 + the index of the last solid of `solids` that covers the cell's centre.
// Throws std::runtime_error when a voxel file cannot be read.
std::vector<std::uint8_t> solid_map(const config::Config& cfg, const std::vector<SolidParams>& solids);

// The number of voxels of a raw or HDF5 image and its shape (x, y, z); an
// error message instead when it cannot be read or its size is not nx ny nz.
std::string check_voxel_file(const SolidParams& s);

// The STL of a mesh solid, scaled and translated; throws std::runtime_error.
stl::TriangleMesh load_solid_mesh(const SolidParams& s);

}  // namespace coflow::fluid
