// What both LBM variants take from the configuration, in lattice units.
#pragma once

#include <algorithm>
#include <array>
#include <functional>
#include <string>

#include "coflow/log.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/lbm/lattice.hpp"
#include "fluid/lbm/params.hpp"
#include "fluid/lbm/units.hpp"

namespace coflow::fluid::lbm {

enum class FaceType { periodic, wall, pressure, velocity, outflow };

struct Face {
  FaceType type = FaceType::wall;
  double rho = 1.0;                 // pressure faces: lattice density (now)
  std::array<double, 3> u{0, 0, 0}; // velocity faces: lattice velocity (now)
  double rho_full = 1.0;            // the values at the end of the ramp
  std::array<double, 3> u_full{0, 0, 0};
  double ramp_steps = 0.0;          // steps of the linear ramp from rest (0: none)
  bool regularized = false;         // pressure/velocity: Latt et al. (2008) instead of Zou-He
};

// Pressure and velocity faces at the step that ends at time (step + 1) dt:
// value x min(1, (step + 1) / ramp_steps).
inline void ramp_faces(std::array<Face, 6>& faces, long step) {
  for (Face& f : faces) {
    const double a = f.ramp_steps > 0.0 ? std::min(1.0, (step + 1) / f.ramp_steps) : 1.0;
    f.rho = 1.0 + a * (f.rho_full - 1.0);
    for (int d = 0; d < 3; ++d) f.u[d] = a * f.u_full[d];
  }
}

struct Setup {
  Units units;
  bool incompressible = true;
  bool d3 = true;                        // D3Q19 (else D2Q9)
  double tau = 0.8;
  bool trt = false;
  double magic = 0.1875;
  std::array<long, 3> cells{1, 1, 1};    // global grid
  std::array<double, 3> lower{0, 0, 0};  // the domain's lower corner, m
  std::array<Face, 6> faces;             // x-, x+, y-, y+, z-, z+
  std::array<double, 3> force{0, 0, 0};  // uniform body force density, lattice units
  bool packed = false;                   // populations packed even where the block fits the spaced stride
  // Initial lattice density and velocity of the cell with global index (i, j, k).
  std::function<void(long i, long j, long k, double& rho, double* u)> initial;
};

// time_step > 0: the step the coupling window asks for (coupler::output_window),
// taken by adjusting tau at the same viscosity.
inline Setup make_setup(const config::Config& cfg, const FluidParams& fp, const LbmParams& lp, double time_step = 0.0) {
  Setup s;
  const auto h = cfg.domain.spacing();
  const double tau = tau_for_step(lp.tau, time_step, h[0], fp.viscosity);
  s.units = Units::from(h[0], fp.viscosity, fp.density, tau);
  s.incompressible = lp.formulation == "incompressible";
  s.d3 = lp.lattice == "D3Q19";
  s.tau = tau;
  s.trt = lp.collision == "trt";
  s.magic = lp.magic;
  s.packed = lp.layout == "packed";
  for (int d = 0; d < 3; ++d) s.cells[d] = cfg.domain.cells[d];
  for (int d = 0; d < 3; ++d) s.lower[d] = cfg.domain.lower[d];
  for (int f = 0; f < 6; ++f) {
    const BoundaryParams b = fp.boundary(f, cfg);
    Face& face = s.faces[f];
    if (b.type == "periodic") face.type = FaceType::periodic;
    if (b.type == "wall") face.type = FaceType::wall;
    if (b.type == "outflow") face.type = FaceType::outflow;
    if (b.type == "pressure") {
      face.type = FaceType::pressure;
      face.rho_full = s.units.lattice_density(b.value.values.at(0));
    }
    if (b.type == "velocity") {
      face.type = FaceType::velocity;
      for (int d = 0; d < 3; ++d) face.u_full[d] = b.value.values.at(d) / s.units.velocity();
    }
    face.ramp_steps = b.ramp / s.units.dt;
    face.regularized = b.closure == "regularized";
    // A 2D run has no z faces: treat them as periodic (one cell, nothing crosses).
    if (cfg.domain.cells[f / 2] == 1) face.type = FaceType::periodic;
  }
  ramp_faces(s.faces, 0);
  for (int d = 0; d < 3; ++d) {
    s.force[d] = fp.body_force[d] / s.units.force_density();
  }
  const Units units = s.units;
  const config::DomainParams dom = cfg.domain;
  s.initial = [&cfg, fp, units, dom](long i, long j, long k, double& rho, double* u) {
    const auto dx = dom.spacing();
    const config::Vec3 x{dom.lower[0] + (i + 0.5) * dx[0], dom.lower[1] + (j + 0.5) * dx[1], dom.lower[2] + (k + 0.5) * dx[2]};
    config::Vec3 us;
    double p;
    fp.initial_state(cfg, x, us, p);
    rho = units.lattice_density(p);
    for (int d = 0; d < 3; ++d) u[d] = us[d] / units.velocity();
  };
  return s;
}

}  // namespace coflow::fluid::lbm
