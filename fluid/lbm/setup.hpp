// What both LBM variants take from the configuration, in lattice units.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "coflow/log.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/lbm/lattice.hpp"
#include "fluid/lbm/params.hpp"
#include "fluid/lbm/units.hpp"
#include "fluid/solid_surface.hpp"

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
  double phase = 0.0;               // two fluids: the colour fraction (rho_r - rho_b) / rho that enters
  bool phase_given = false;         // else what enters takes the colour of the face's cell
  // A velocity face's profile (parabolic, table, expression): the factor on u
  // at each of its nodes, by global index along its other two axes (the lower
  // one fastest; factor_n nodes along it); empty: uniform.
  std::vector<double> factor;
  long factor_n = 1;
  // A formula in time: the factor at node (a, b) and time t in s, and the
  // step's length in s; ramp_faces sets `factor` again at each step.
  std::function<double(long a, long b, double t)> factor_at;
  double dt = 0.0;

  // The face's velocity (lattice units, now) at the node with global indices g.
  void velocity(const long g[3], int axis, double out[3]) const {
    double c = 1.0;
    if (!factor.empty())
      c = factor[static_cast<std::size_t>(g[axis == 0 ? 1 : 0] + factor_n * g[axis == 2 ? 1 : 2])];
    for (int d = 0; d < 3; ++d) out[d] = factor.empty() ? u[d] : c * u[d];
  }
  // The factors at time t (s): every node of the face.
  void set_factors(double t) {
    const long n = static_cast<long>(factor.size()) / factor_n;
    for (long b = 0; b < n; ++b)
      for (long a = 0; a < factor_n; ++a)
        factor[static_cast<std::size_t>(a + factor_n * b)] = factor_at(a, b, t);
  }
};

// Pressure and velocity faces at the step that ends at time (step + 1) dt:
// value x min(1, (step + 1) / ramp_steps).
inline void ramp_faces(std::array<Face, 6>& faces, long step) {
  for (Face& f : faces) {
    const double a = f.ramp_steps > 0.0 ? std::min(1.0, (step + 1) / f.ramp_steps) : 1.0;
    f.rho = 1.0 + a * (f.rho_full - 1.0);
    for (int d = 0; d < 3; ++d) f.u[d] = a * f.u_full[d];
    if (f.factor_at) f.set_factors((step + 1) * f.dt);
  }
}

// Two fluids (colour gradient, seed 000 §2.3.4) and interior solids.
struct TwoPhase {
  bool on = false;               // two fluids; else interior solids in one (red) fluid
  double gamma = 0.0;            // surface tension, lattice units
  double beta = 0.7;
  double tau_blue = 0.8;
  bool geometric = true;         // wetting: geometric (turn the colour gradient), else the seed's fixed colour
  // The colour field phi: (rho_r - rho_b) / (rho_r + rho_b); else rho_r - rho_b (seed 000 eq. 2.56).
  bool phase_field = false;
  double wall_phase = 1.0;       // the box's walls: cos(theta), = their colour phi_s in the seed's wetting
  std::vector<double> solid_phase;  // cos(theta) of solid n at index n (0: unused)
  // Solid id per global cell (x fastest; 0 fluid); empty: no interior solids.
  std::shared_ptr<const std::vector<std::uint8_t>> solids;
  // fluid.lbm.bounce_back interpolated or central: where the links cross the solids' surfaces; null:
  // halfway.
  std::shared_ptr<const SolidSurface> surface;
  bool central = false;  // central: Ginzburg's central linear interpolation, else Bouzidi's
  // Initial colour (+1 red, -1 blue) of the cell with global index (i, j, k).
  std::function<double(long i, long j, long k)> initial_phase;
  bool any_solid() const { return solids && !solids->empty(); }
};

struct Setup {
  Units units;
  TwoPhase tp;                           // two fluids, or interior solids; else off
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

// The colours, viscosities and solids of a two-phase fluid or of one with
// interior solids.
inline void set_two_phase(Setup& s, const config::Config& cfg, const FluidParams& fp) {
  TwoPhase& t = s.tp;
  t.on = fp.two_phase.on;
  const double deg = std::numbers::pi / 180.0;
  if (t.on) {
    const Units& u = s.units;
    t.gamma = fp.two_phase.surface_tension * u.dt * u.dt / (u.rho * u.dx * u.dx * u.dx);
    t.beta = fp.two_phase.beta;
    t.tau_blue = 0.5 + 3.0 * fp.two_phase.viscosity_blue * u.dt / (u.dx * u.dx);
    t.wall_phase = std::cos(fp.two_phase.contact_angle * deg);
    t.geometric = fp.two_phase.wetting == "geometric";
    t.phase_field = fp.two_phase.colour_field == "phase";
  }
  t.solid_phase.assign(1, 0.0);
  for (const auto& sp : fp.solids)
    t.solid_phase.push_back(!t.on ? 1.0 : std::cos((sp.contact_angle < 0 ? fp.two_phase.contact_angle : sp.contact_angle) * deg));
  if (!fp.solids.empty()) t.solids = std::make_shared<const std::vector<std::uint8_t>>(solid_map(cfg, fp.solids));
  const config::DomainParams dom = cfg.domain;
  const auto regions = fp.initial_phase;
  t.initial_phase = [dom, regions](long i, long j, long k) {
    const auto dx = dom.spacing();
    return painted_phase(regions, {dom.lower[0] + (i + 0.5) * dx[0], dom.lower[1] + (j + 0.5) * dx[1],
                                   dom.lower[2] + (k + 0.5) * dx[2]});
  };
}

// A velocity face's profile at its nodes, the centres of the face's cells,
// where lbm imposes the face's value: BoundaryParams::profile_factor at their
// fractions of the box (a parabola or a table across the face), and a formula
// at the node itself (h/2 inside the box along the normal, unlike fv, whose
// faces lie on the box's planes). A formula in t is set again at each step's
// end time (ramp_faces); the configuration outlives the solvers that read it.
inline void set_profile(Face& face, int f, const BoundaryParams& b, const config::Config& cfg, double dt) {
  const int axis = f / 2, ta = axis == 0 ? 1 : 0, tb = axis == 2 ? 1 : 2;
  const auto& n = cfg.domain.cells;
  face.factor_n = n[ta];
  face.factor.assign(static_cast<std::size_t>(n[ta] * n[tb]), 1.0);
  face.dt = dt;
  face.factor_at = [b, f, ta, tb, &cfg](long a, long c, double t) {
    const auto& d = cfg.domain;
    double s[3] = {0.5, 0.5, 0.5};
    s[f / 2] = (f % 2 == 0 ? 0.5 : d.cells[f / 2] - 0.5) / d.cells[f / 2];
    s[ta] = (a + 0.5) / d.cells[ta];
    s[tb] = (c + 0.5) / d.cells[tb];
    if (b.profile != "expression") return b.profile_factor(f, s, cfg, t);
    double x[3];
    for (int k = 0; k < 3; ++k) x[k] = d.lower[k] + s[k] * (d.upper[k] - d.lower[k]);
    return b.formula(x, t);
  };
  face.set_factors(0.0);
  if (b.profile != "expression" || !b.formula.uses_time()) face.factor_at = nullptr;
}

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
    if (b.type == "velocity" && b.profile != "uniform") set_profile(face, f, b, cfg, s.units.dt);
    face.ramp_steps = b.ramp / s.units.dt;
    face.regularized = b.closure == "regularized";
    face.phase_given = !b.phase.empty();
    face.phase = b.phase == "blue" ? -1.0 : 1.0;
    // A 2D run has no z faces: treat them as periodic (one cell, nothing crosses).
    if (cfg.domain.cells[f / 2] == 1) face.type = FaceType::periodic;
  }
  ramp_faces(s.faces, 0);
  for (int d = 0; d < 3; ++d) {
    s.force[d] = fp.body_force[d] / s.units.force_density();
  }
  set_two_phase(s, cfg, fp);
  if (!fp.solids.empty() && lp.bounce_back != "halfway")
    s.tp.surface = std::make_shared<const SolidSurface>(cfg, fp.solids);
  s.tp.central = lp.bounce_back == "central";
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
