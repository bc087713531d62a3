// The configuration both point-particle (DPM) variants take: faces, walls,
// collision coefficients, forces, gravity, the fluid seen without a coupling
// partner, and the Lagrangian time step of seed 003 eq. 4.15.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "coflow/log.hpp"
#include "particles/dem/contact.hpp"
#include "particles/dem/dem_common.hpp"
#include "particles/dpm/collision.hpp"
#include "particles/dpm/dispersion.hpp"
#include "particles/dpm/forces.hpp"
#include "particles/particles_interface.hpp"
#include "particles/store/grid_cell.hpp"

namespace coflow::particles::dpm {

enum class Face { periodic, wall, outlet, symmetry };

struct DpmSetup {
  std::array<Face, 6> faces{};
  std::array<Restitution, 6> wall{};  // per face: wall coefficients (symmetry: e = 1, mu = 0)
  Restitution pair;                   // particle-particle (default)
  std::vector<Restitution> pairs;     // per species pair, ns x ns
  std::vector<std::string> species_names;
  int ns = 0;
  const Restitution& pair_law(int a, int b) const { return pairs[static_cast<std::size_t>(a * ns + b)]; }
  bool collisions = true;
  ForceSet forces;
  Dispersion dispersion;
  V3 gravity = V3::Zero();
  V3 lower = V3::Zero(), upper = V3::Zero();
  std::array<bool, 3> periodic{false, false, false};
  double cell = 0.0;                  // the fluid cells' narrowest side (t_V.C of eq. 4.15)
  V3 spacing = V3::Ones();            // fluid cell sizes along x, y, z (cells of the tau_c estimate)
  std::array<long, 3> cells{1, 1, 1};  // the fluid grid's cells along x, y, z (domain.cells)
  FluidSample still;                  // the fluid without a coupling partner: at rest
  bool auto_step = true;
  double dt = 0.0;                    // the configured step (auto: the start's eq. 4.15 value)
  // triangle-mesh walls (STL), each with its coefficients
  std::vector<std::shared_ptr<const dem::MeshWall>> meshes;
  std::vector<Restitution> mesh_law;
  bool mesh_all_triangles = false;    // test every triangle (the oracle) instead of FCL's candidates
};

// The domain's length along its periodic axes, 0 along the others.
inline V3 periods(const DpmSetup& s) {
  V3 L = V3::Zero();
  for (int k = 0; k < 3; ++k)
    if (s.periodic[k]) L[k] = s.upper[k] - s.lower[k];
  return L;
}

// Wall keys of events and impacts: faces 0-5, triangle t of mesh m 6 + (m << 24) + t.
inline std::int64_t mesh_key(std::size_t m, int t) { return 6 + (static_cast<std::int64_t>(m) << 24) + t; }

inline DpmSetup make_setup(const ParticleParams& p, const config::Config& cfg) {
  DpmSetup s;
  for (int d = 0; d < 3; ++d) {
    s.gravity[d] = cfg.gravity[d];
    s.lower[d] = cfg.domain.lower[d];
    s.upper[d] = cfg.domain.upper[d];
    s.periodic[d] = cfg.domain.periodic[d];
  }
  for (int d = 0; d < 3; ++d) {
    s.spacing[d] = cfg.domain.spacing()[d];
    s.cells[d] = cfg.domain.cells[d];
  }
  // The narrowest side (no cell crossed in fewer than 5 steps) of the axes
  // with cells to cross (a 2D grid's depth is none).
  s.cell = std::numeric_limits<double>::infinity();
  for (int d = 0; d < 3; ++d)
    if (cfg.domain.cells[d] > 1 || d == 0) s.cell = std::min(s.cell, s.spacing[d]);
  s.pair = {p.collision.restitution, p.collision.friction};
  s.ns = static_cast<int>(p.species.size());
  for (const auto& sp : p.species) s.species_names.push_back(sp.first);
  s.pairs.assign(static_cast<std::size_t>(s.ns * s.ns), s.pair);
  for (const auto& pp : p.collision.pairs) {
    const int a = p.species_index(pp.species.at(0)), b = p.species_index(pp.species.at(1));
    s.pairs[static_cast<std::size_t>(a * s.ns + b)] = s.pairs[static_cast<std::size_t>(b * s.ns + a)] = {
        pp.restitution, pp.friction};
  }
  s.collisions = p.collision.enabled;
  auto has = [&](const char* f) { return std::find(p.forces.begin(), p.forces.end(), f) != p.forces.end(); };
  s.forces = {has("gravity_buoyancy"), has("drag"), has("saffman_lift"), has("magnus_lift"), has("torque")};
  s.dispersion = {p.dispersion.model == "langevin", p.dispersion.C_T, static_cast<std::uint64_t>(cfg.run.seed)};
  const char* names[] = {"x-", "x+", "y-", "y+", "z-", "z+"};
  for (int f = 0; f < 6; ++f) {
    s.wall[f] = s.pair;
    if (cfg.domain.periodic[f / 2]) {
      s.faces[f] = Face::periodic;
      continue;
    }
    const std::string& b = p.boundaries[f];
    s.faces[f] = b == "outlet" ? Face::outlet : b == "symmetry" ? Face::symmetry : Face::wall;
    if (s.faces[f] == Face::symmetry) s.wall[f] = {1.0, 0.0};
    for (const auto& w : p.walls)
      if (w.face == names[f]) {
        s.faces[f] = Face::wall;
        s.wall[f] = {w.restitution, w.friction >= 0 ? w.friction : p.collision.friction};
      }
  }
  for (const auto& w : p.walls)
    if (!w.mesh.empty()) {
      dem::TriangleMesh m = load_mesh(w);
      log::info("mesh wall {}", describe_mesh(w, m));
      s.meshes.push_back(std::make_shared<const dem::MeshWall>(std::move(m), w.friction));
      s.mesh_law.push_back({w.restitution, w.friction >= 0 ? w.friction : p.collision.friction});
    }
  // Without a coupling partner the particles see the fluid section's fluid, at rest.
  const auto fl = cfg.resolved["fluid"];
  if (fl && fl["density"] && fl["viscosity"]) {
    s.still.rho = fl["density"].as<double>();
    s.still.mu = s.still.rho * fl["viscosity"].as<double>();
  }
  s.auto_step = p.time_step.is_auto;
  s.dt = p.time_step.is_auto ? 0.0 : p.time_step.value;
  return s;
}

// The time step of eq. 4.15 for one particle: 0.2 x min(cell crossing time,
// response time); the collision time scale enters through the caller (mean
// free time from the number density), the Lagrangian integral time with the
// dispersion model. Eq. 4.15's response time is Stokes' (eq. 2.17); beyond
// Re_p of about 55 the drag relaxes the slip faster than that, at
// drag_rate(Re_p) / tau_p, and RK4 (stable for h lambda < 2.785) would
// diverge past Re_p of about 300: the step is also kept to h lambda <= 1,
// with the slip of the mean flow, and with dispersion 3 sqrt(2 k) more (the
// fluctuation the particle may see; drawn after this step is chosen).
inline constexpr double kLagrangianStepFraction = 0.2;  // of the smallest time of eq. 4.15
inline double lagrangian_step(const DpmSetup& s, double D, double rho_p, const V3& v, const FluidSample& f) {
  double t = std::numeric_limits<double>::infinity();
  const double speed = v.norm();
  if (speed > 0.0) t = std::min(t, s.cell / speed);
  if (f.mu > 0.0 && s.forces.drag) {
    const double slip =
        (f.u - v).norm() + (s.dispersion.on ? 3.0 * std::sqrt(2.0 * std::max(f.k, 0.0)) : 0.0);
    const double tau = response_time(rho_p, D, f.mu), re_p = f.rho * D * slip / f.mu;
    t = std::min({t, tau, 5.0 * tau / drag_rate(re_p)});
  }
  if (s.dispersion.on && lagrangian_time(f, s.dispersion.C_T) > 0.0) t = std::min(t, lagrangian_time(f, s.dispersion.C_T));
  return kLagrangianStepFraction * t;
}

// The mean time between collisions tau_c of eq. 4.15, the inverse of the
// collision frequency (seed 003 §2.2.1.2), from kinetic theory in each fluid
// cell: a particle meets the cell's others at f = n pi D^2 g, with n the cell's
// number density, D its mean diameter and g the mean relative speed of a
// Maxwellian at the cell's granular temperature T = <|v - <v>|^2> / 3,
// g = sqrt(16 T / pi); so f = 4 n D^2 sqrt(pi T), seed 003 eq. 5.9 per particle
// with g0 = 1. The particle ranks' blocks are whole fluid cells, and a
// particle's cell is the one that decides its owner (store::grid_cell), so a
// cell's particles are on one rank. Returns the smallest tau_c over the cells holding
// two or more particles (infinity where none does). x(i), v(i), D(i): the
// position, velocity and diameter of particle i of n.
template <class Pos, class Vel, class Diam>
double mean_collision_time(std::size_t n, Pos x, Vel v, Diam D, const DpmSetup& s) {
  struct Cell {
    long count = 0;
    double D = 0.0;
    V3 v = V3::Zero();
    double v2 = 0.0;
  };
  std::map<std::array<long, 3>, Cell> cells;
  for (std::size_t i = 0; i < n; ++i) {
    std::array<long, 3> key;
    for (int d = 0; d < 3; ++d) key[d] = store::grid_cell(x(i)[d], s.lower[d], s.upper[d], s.cells[d]);
    Cell& c = cells[key];
    ++c.count;
    c.D += D(i);
    c.v += v(i);
    c.v2 += v(i).squaredNorm();
  }
  const double volume = s.spacing[0] * s.spacing[1] * s.spacing[2];
  double tau = std::numeric_limits<double>::infinity();
  for (const auto& [key, c] : cells) {
    if (c.count < 2) continue;
    const double k = static_cast<double>(c.count);
    double T = (c.v2 / k - (c.v / k).squaredNorm()) / 3.0;
    if (T <= 1e-12 * c.v2 / k) T = 0.0;  // no spread of velocities but round-off
    const double Dm = c.D / k;
    const double f = 4.0 * (k / volume) * Dm * Dm * std::sqrt(std::numbers::pi * T);
    if (f > 0.0) tau = std::min(tau, 1.0 / f);
  }
  return tau;
}

// Distance from x to the plane of face f (positive inside the box) and the unit
// normal pointing out of the box through f.
inline double face_distance(int f, const V3& x, const DpmSetup& s) {
  const int a = f / 2;
  return f % 2 == 0 ? x[a] - s.lower[a] : s.upper[a] - x[a];
}
inline V3 face_normal(int f) {
  V3 n = V3::Zero();
  n[f / 2] = f % 2 == 0 ? -1.0 : 1.0;
  return n;
}

// One particle over a step h: fluid forces and gravity-buoyancy integrated with
// the classical RK4 (seed 003 eqs 4.12-4.14) on (x, v, w), the fluid at the
// particle held over the step.
struct Motion {
  V3 x, v, w;
  V3 impulse = V3::Zero();  // of the fluid forces over the step, N s (eq. 3.43)
  unsigned beyond = 0;      // correlations used outside their range (forces.hpp, Beyond)
};
inline Motion rk4(const Motion& s, double D, double m, double I, double rho_p, const FluidSample& fluid,
                  const DpmSetup& set, double h) {
  const V3 g = set.forces.gravity_buoyancy ? V3(gravity_buoyancy(1.0, rho_p, fluid.rho, set.gravity)) : V3(V3::Zero());
  V3 J = V3::Zero();
  unsigned beyond = 0;
  auto rate = [&](const V3& v, const V3& w, V3& dv, V3& dw, double weight) {
    const FluidLoad L = fluid_load(fluid, D, v, w, set.forces);
    beyond |= L.beyond;
    J += weight * L.force();
    dv = L.force() / m + g;  // eq. 3.29
    dw = L.torque / I;       // eq. 3.30
  };
  V3 a1, b1, a2, b2, a3, b3, a4, b4;
  rate(s.v, s.w, a1, b1, h / 6.0);
  const V3 v2 = s.v + 0.5 * h * a1, w2 = s.w + 0.5 * h * b1;
  rate(v2, w2, a2, b2, h / 3.0);
  const V3 v3 = s.v + 0.5 * h * a2, w3 = s.w + 0.5 * h * b2;
  rate(v3, w3, a3, b3, h / 3.0);
  const V3 v4 = s.v + h * a3, w4 = s.w + h * b3;
  rate(v4, w4, a4, b4, h / 6.0);
  return {s.x + h / 6.0 * (s.v + 2.0 * v2 + 2.0 * v3 + v4), s.v + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4),
          s.w + h / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4), J, beyond};
}

// A collision found in a step: time, the two ids (b < 0: the wall face -1 - b)
// and the local indices. Events are processed in (t, a, b) order by both
// variants, so that they take the same decisions.
struct Event {
  double t;
  std::int64_t a, b;
  std::size_t i, j;
  bool operator<(const Event& o) const {
    if (t != o.t) return t < o.t;
    if (a != o.a) return a < o.a;
    return b < o.b;
  }
};

// Separation a - b with the minimum image on periodic axes (both in the box).
using dem::min_image;

// Wall and symmetry faces that particle i (centre x, trajectory velocity u,
// diameter D) reaches within the step h: events (t, id, -1 - face).
inline void wall_events(const V3& x, const V3& u, double D, std::int64_t id, std::size_t i, double h,
                        const DpmSetup& s, std::vector<Event>& out) {
  for (int f = 0; f < 6; ++f) {
    if (s.faces[f] != Face::wall && s.faces[f] != Face::symmetry) continue;
    const double un = u.dot(face_normal(f));
    if (un <= 0.0) continue;
    const double t = std::max(0.0, (face_distance(f, x, s) - 0.5 * D) / un);
    if (t < h) out.push_back({t, id, -1 - f, i, i});
  }
}

// Triangle-mesh walls that particle i reaches within the step h (swept sphere
// against triangle, collision.hpp): the earliest contact per mesh, as an event
// (t, id, -1 - mesh_key). Candidates come from FCL's BVH (Algorithm 2: only
// triangles near the trajectory are tested), or from every triangle when
// s.mesh_all_triangles (dpm-reference). Ties between triangles (a shared edge
// or vertex) go to the lower triangle index.
inline void mesh_events(const V3& x, const V3& u, double D, std::int64_t id, std::size_t i, double h,
                        const DpmSetup& s, std::vector<int>& scratch, std::vector<Event>& out) {
  for (std::size_t m = 0; m < s.meshes.size(); ++m) {
    const dem::MeshWall& mesh = *s.meshes[m];
    if (s.mesh_all_triangles) {
      scratch.resize(mesh.size());
      for (std::size_t t = 0; t < mesh.size(); ++t) scratch[t] = static_cast<int>(t);
    } else {
      mesh.swept_candidates(x, x + u * h, 0.5 * D, scratch);
    }
    double best = std::numeric_limits<double>::infinity();
    int hit = -1;
    V3 point;
    for (int t : scratch) {
      const double tc = sweep_triangle(x, u, 0.5 * D, h, mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2), point);
      if (tc < best) {
        best = tc;
        hit = t;
      }
    }
    if (hit >= 0) out.push_back({best, id, -1 - mesh_key(m, hit), i, i});
  }
}

// The slot of a wall event's wall (b < 0) in WallImpulse: its face (0-5), or
// 6 + its mesh.
inline std::size_t wall_slot(std::int64_t b) {
  const std::int64_t key = -1 - b;
  return key < 6 ? static_cast<std::size_t>(key) : 6 + static_cast<std::size_t>((key - 6) >> 24);
}

// Whether a wall event (b < 0) is a symmetry face's mirror: the particle is
// reflected, but no wall is hit (no wall collision, no impact; the momentum
// it takes stays in the face's column of walls.csv, for the balance).
inline bool mirror_event(std::int64_t b, const DpmSetup& s) {
  const std::int64_t key = -1 - b;
  return key < 6 && s.faces[static_cast<std::size_t>(key)] == Face::symmetry;
}

// The wall of a wall event (b < 0): unit normal from the particle into the
// wall at contact, the contact point and the coefficients. x, u: the particle's
// position at the step's start and its trajectory velocity.
inline void wall_contact(std::int64_t b, const V3& x, const V3& u, double t, double D, const DpmSetup& s, V3& normal,
                         V3& point, const Restitution*& law) {
  const std::int64_t key = -1 - b;
  const V3 c = x + u * t;
  if (key < 6) {
    const int f = static_cast<int>(key);
    normal = face_normal(f);
    point = c + 0.5 * D * normal;
    law = &s.wall[f];
    return;
  }
  const auto m = static_cast<std::size_t>((key - 6) >> 24);
  const int tri = static_cast<int>((key - 6) & 0xffffff);
  const dem::MeshWall& mesh = *s.meshes[m];
  V3 p;
  sweep_triangle(x, u, 0.5 * D, std::numeric_limits<double>::infinity(), mesh.vertex(tri, 0), mesh.vertex(tri, 1),
                 mesh.vertex(tri, 2), p);
  point = p;
  normal = (p - c).normalized();
  law = &s.mesh_law[m];
}

// The rest of a step after a particle's first event (eqs 4.30-4.31): from the
// contact centre c it moves with its new velocity v for `rest`; a wall face
// or mesh it reaches there takes it too, at most kMoreWallEvents times (a pair
// collision can drive it into a wall within the step; a thin mesh would
// otherwise be passed through for good). on_wall(t, key, point, normal,
// before) hears of each impulse applied, t from c's time. Returns the
// position at the step's end; at the last contact when the events run out
// (a particle caught between walls stops there rather than pass one). A
// contact with no approach to speak of (after a bounce with e = 0, round-off)
// ends the checks: the particle slides on.
inline constexpr int kMoreWallEvents = 4;
template <class OnWall>
inline V3 finish_step(V3 c, V3& v, V3& w, double rest, double D, std::int64_t id, const DpmSetup& s,
                      std::vector<int>& scratch, OnWall&& on_wall) {
  std::vector<Event> ev;
  double t0 = 0.0;
  for (int k = 0; k < kMoreWallEvents; ++k) {
    ev.clear();
    wall_events(c, v, D, id, 0, rest, s, ev);
    if (!s.meshes.empty()) mesh_events(c, v, D, id, 0, rest, s, scratch, ev);
    if (ev.empty()) break;
    const Event e = *std::min_element(ev.begin(), ev.end());
    V3 normal, point;
    const Restitution* law = nullptr;
    wall_contact(e.b, c, v, e.t, D, s, normal, point, law);
    if (v.dot(normal) <= 1e-12 * v.norm()) break;
    const V3 before = v;
    c += v * e.t;
    rest -= e.t;
    t0 += e.t;
    if (collide_wall(v, w, D, normal, *law)) on_wall(t0, e.b, point, normal, before);
    if (k + 1 == kMoreWallEvents) return c;
  }
  return c + v * rest;
}

// Periodic faces wrap x back into the box; returns false when the particle left
// through an outlet.
inline bool apply_faces(V3& x, const DpmSetup& s) {
  bool out = false;
  for (int k = 0; k < 3; ++k) {
    const double L = s.upper[k] - s.lower[k];
    if (s.periodic[k]) {
      if (x[k] < s.lower[k]) x[k] += L;
      if (x[k] >= s.upper[k]) x[k] -= L;
    } else {
      out = out || (x[k] < s.lower[k] && s.faces[2 * k] == Face::outlet) ||
            (x[k] > s.upper[k] && s.faces[2 * k + 1] == Face::outlet);
    }
  }
  return !out;
}

// Sub-steps of one step h so that each is no longer than the Lagrangian step
// of eq. 4.15 (`stable`), when the step is automatic.
inline long lagrangian_substeps(const DpmSetup& s, double h, double stable) {
  return s.auto_step
             ? dem::split_for(h, stable,
                              "a particle has become too fast or too small for eq. 4.15's step: check "
                              "the species, the inlets' speeds and the fluid's velocity")
             : 1;
}

}  // namespace coflow::particles::dpm
