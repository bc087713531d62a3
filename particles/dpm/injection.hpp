// Particle inlets of the point-particle variants (seed 003 §4.2.2.4): a mass
// flow through a disk or a rectangle. Each step owes the inlet's mass flow
// times the step (eq. 4.18); whole particles are injected while the next
// particle's mass fits what is owed, and the remainder is carried to the next
// step (eq. 4.19 truncates it, which loses mass when a step holds few
// particles). Sizes come from the species' distribution (fixed, uniform,
// log-normal of eqs 4.20-4.21 with the corrected sigma). Each particle enters
// at a random instant of the step and a random point of the face (uniform over
// the area) and has moved on from there by the end of the step; its direction
// is uniform over the cone of half-angle spread_angle about the jet direction
// (the 3D form of eq. 5.20's opening angle). Candidates that would overlap a
// particle near the inlet are drawn again (64 times); a particle that finds no
// room waits for the next step, which draws it 64 new places. Until the next coupling window an entering
// particle sees the fluid sampled at the window's start at the inlet's probe nearest to its entry point
// (set_probe_lattice). Random numbers derive from (run.seed, inlet, particle serial, attempt) only, so dpm
// and dpm-reference inject the same particles.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "particles/dpm/dispersion.hpp"
#include "particles/dpm/forces.hpp"
#include "particles/particles_interface.hpp"
#include "particles/size_distribution.hpp"

namespace coflow::particles::dpm {

struct Inlet {
  int species = 0;
  double density = 0.0;
  config::Distribution diameter;
  double dmax = 0.0;  // the largest diameter drawn (mean + 6 std for log-normal)
  double mass_flow = 0.0, speed = 0.0, cos_spread = 1.0, start = 0.0, stop = -1.0;
  bool disk = true;
  V3 center = V3::Zero(), normal = V3::Zero(), t1 = V3::Zero(), t2 = V3::Zero(), dir = V3::Zero();
  double radius = 0.0, a = 0.0, b = 0.0;
  // The probe lattice (set_probe_lattice): points probe_step apart on the face,
  // (2 probe_n[0] + 1) x (2 probe_n[1] + 1) of them along t1 and t2.
  double probe_step = 0.0;
  int probe_n[2] = {0, 0};
  // The domain's lower corner and its length along periodic axes (0 along
  // the others): entering particles and their neighbours are compared as
  // nearest images, and enter wrapped into the domain.
  V3 lower = V3::Zero(), period = V3::Zero();
  // state (checkpointed)
  double owed = 0.0;      // kg delivered by the flow and not yet injected
  std::int64_t serial = 0;  // particles injected so far
  std::int64_t tries = 0;   // places drawn in vain for the next particle, in earlier steps
};

// A particle entering in this step: its state at the step's end, and the
// point of the face where it entered.
struct Entering {
  V3 x, v, entry;
  double D;
  int species;
};

// Two unit vectors completing n to an orthonormal basis; `hint` (if not
// parallel to n) gives the direction of the first.
inline void basis(const V3& n, const V3& hint, V3& e1, V3& e2) {
  V3 h = hint;
  if (h.squaredNorm() == 0.0 || std::abs(h.normalized().dot(n)) > 0.999) {
    int k = 0;  // the coordinate axis most normal to n
    for (int d = 1; d < 3; ++d)
      if (std::abs(n[d]) < std::abs(n[k])) k = d;
    h = V3::Zero();
    h[k] = 1.0;
  }
  e1 = (h - h.dot(n) * n).normalized();
  e2 = n.cross(e1);
}

inline void set_probe_lattice(Inlet& in, double cell);

// d as the nearest of its periodic images (an axis of period 0 is not
// periodic).
inline V3 nearest_image(V3 d, const V3& period) {
  for (int k = 0; k < 3; ++k)
    if (period[k] > 0.0) d[k] -= period[k] * std::round(d[k] / period[k]);
  return d;
}

// x moved into the domain along its periodic axes (unchanged where inside).
inline V3 wrapped(V3 x, const V3& lower, const V3& period) {
  for (int k = 0; k < 3; ++k) {
    if (!(period[k] > 0.0)) continue;
    double t = x[k] - lower[k];
    if (t >= 0.0 && t < period[k]) continue;
    t -= period[k] * std::floor(t / period[k]);
    x[k] = lower[k] + (t < period[k] ? t : 0.0);  // t rounds up to period[k] only from just below 0
  }
  return x;
}

// The inlets of a domain from `lower` with `period` (see Inlet), with probe
// lattices for a fluid whose narrowest cell side is `cell`.
inline std::vector<Inlet> make_inlets(const ParticleParams& p, double cell, const V3& lower,
                                      const V3& period) {
  std::vector<Inlet> out;
  for (const InjectionParams& ip : p.injection) {
    Inlet in;
    in.lower = lower;
    in.period = period;
    in.species = p.species_index(ip.species);
    const SpeciesParams& sp = p.species.at(static_cast<std::size_t>(in.species)).second;
    in.density = sp.density;
    in.diameter = sp.diameter;
    in.dmax = largest_diameter(sp.diameter);
    in.mass_flow = ip.mass_flow;
    in.speed = ip.speed;
    in.cos_spread = std::cos(ip.spread_angle * std::numbers::pi / 180.0);
    in.start = ip.start;
    in.stop = ip.stop;
    in.disk = ip.disk;
    in.center = V3(ip.center.data());
    in.normal = V3(ip.normal.data()).normalized();
    basis(in.normal, V3(ip.axis.data()), in.t1, in.t2);
    const V3 d(ip.direction.data());
    in.dir = d.squaredNorm() > 0.0 ? V3(d.normalized()) : in.normal;
    in.radius = 0.5 * ip.diameter;
    in.a = ip.size[0];
    in.b = ip.size[1];
    set_probe_lattice(in, cell);
    out.push_back(in);
  }
  return out;
}

// A uniform number in (0, 1) for (seed, inlet, serial, attempt, component).
inline double inlet_uniform(std::uint64_t seed, int inlet, std::int64_t serial, std::int64_t attempt,
                            int component) {
  const std::uint64_t h = mix(mix(mix(mix(seed ^ 0x51ed27f1a3c4e9b7ULL ^ static_cast<std::uint64_t>(inlet)) ^
                                      static_cast<std::uint64_t>(serial)) ^
                                  static_cast<std::uint64_t>(attempt)) ^
                              static_cast<std::uint64_t>(component));
  return (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
}

inline double inlet_diameter(const Inlet& in, std::uint64_t seed, int k) {
  const config::Distribution& d = in.diameter;
  const double u1 = inlet_uniform(seed, k, in.serial, 0, 0);
  switch (d.kind) {
    case config::Distribution::Kind::fixed: return d.a;
    case config::Distribution::Kind::uniform: return d.a + (d.b - d.a) * u1;
    case config::Distribution::Kind::lognormal: {
      // Box-Muller from the r-th pair of this particle's uniforms (attempt 0).
      auto normal = [&](int r) {
        const double a = r == 0 ? u1 : inlet_uniform(seed, k, in.serial, 0, 2 * r);
        const double b = inlet_uniform(seed, k, in.serial, 0, 2 * r + 1);
        return std::sqrt(-2.0 * std::log(a)) * std::cos(2.0 * std::numbers::pi * b);
      };
      return truncated_lognormal(d.a, d.b, normal);
    }
  }
  return d.a;
}

// The particles entering through inlet k over the step [t, t + h). `nearby`
// holds (position, diameter) of the particles that may touch an entering one;
// the entering ones are added to it.
inline void inject(Inlet& in, int k, std::uint64_t seed, double t, double h,
                   std::vector<std::pair<V3, double>>& nearby, std::vector<Entering>& out) {
  const double t0 = std::max(t, in.start), t1 = in.stop >= 0.0 ? std::min(t + h, in.stop) : t + h;
  if (t1 > t0) in.owed += in.mass_flow * (t1 - t0);
  while (true) {
    const double D = inlet_diameter(in, seed, k);
    const double m = in.density * std::numbers::pi * D * D * D / 6.0;
    if (m > in.owed) return;
    bool placed = false;
    for (std::int64_t attempt = in.tries + 1; attempt <= in.tries + 64 && !placed; ++attempt) {
      auto u = [&](int c) { return inlet_uniform(seed, k, in.serial, attempt, c); };
      // entry instant within [t0, t1), entry point on the face
      const double te = t0 + (t1 > t0 ? u(0) * (t1 - t0) : 0.0);
      V3 p = in.center;
      if (in.disk) {
        const double r = in.radius * std::sqrt(u(1)), phi = 2.0 * std::numbers::pi * u(2);
        p += r * (std::cos(phi) * in.t1 + std::sin(phi) * in.t2);
      } else {
        p += (u(1) - 0.5) * in.a * in.t1 + (u(2) - 0.5) * in.b * in.t2;
      }
      // direction uniform over the cone's solid angle
      const double c = 1.0 - u(3) * (1.0 - in.cos_spread), s = std::sqrt(std::max(0.0, 1.0 - c * c));
      const double psi = 2.0 * std::numbers::pi * u(4);
      V3 e1, e2;
      basis(in.dir, in.t1, e1, e2);
      const V3 v = in.speed * (c * in.dir + s * (std::cos(psi) * e1 + std::sin(psi) * e2));
      V3 x = p + v * (t + h - te);
      x = wrapped(x, in.lower, in.period);
      bool free = true;
      for (const auto& [y, Dy] : nearby)
        if (nearest_image(y - x, in.period).squaredNorm() < 0.25 * (D + Dy) * (D + Dy)) {
          free = false;
          break;
        }
      if (!free) continue;
      out.push_back({x, v, p, D, in.species});
      nearby.emplace_back(x, D);
      placed = true;
    }
    if (!placed) {     // no room this step: the particle waits, its mass stays owed, and
      in.tries += 64;  // the next step draws 64 other places (a blocked few never stall the inlet)
      return;
    }
    in.owed -= m;
    ++in.serial;
    in.tries = 0;
  }
}

// Whether a particle of diameter D at x may touch one entering through the
// inlet in a step h: an entering one ends the step within half + speed h of
// the inlet's centre and touches x within (dmax + D) / 2 of it (with a margin
// for rounding).
inline bool near_inlet(const Inlet& in, double h, const V3& x, double D) {
  const double half = in.disk ? in.radius : 0.5 * std::hypot(in.a, in.b);
  const double reach = half + in.speed * h + 0.5 * (in.dmax + D);
  return nearest_image(x - in.center, in.period).norm() < reach * (1.0 + 1e-9);
}

// The fluid an entering particle sees until the next coupling window (a
// particle injected within a window has no sample of its own): the fluid
// sampled at the start of the window at the probe point of its inlet nearest
// to where it entered. The probes form a square lattice on the face, about
// half the finest fluid cell apart (at most 33 x 33 points: coarser for
// inlets wider than 16 cells), covering the disk or rectangle.
inline void set_probe_lattice(Inlet& in, double cell) {
  const double half[2] = {in.disk ? in.radius : 0.5 * in.a, in.disk ? in.radius : 0.5 * in.b};
  in.probe_step = std::max({0.5 * cell, half[0] / 16.0, half[1] / 16.0});
  for (int d = 0; d < 2; ++d) in.probe_n[d] = static_cast<int>(std::ceil(half[d] / in.probe_step - 1e-9));
}

inline std::size_t probe_count(const Inlet& in) {
  return static_cast<std::size_t>((2 * in.probe_n[0] + 1) * (2 * in.probe_n[1] + 1));
}

inline V3 probe_point(const Inlet& in, std::size_t q) {
  const int m = 2 * in.probe_n[1] + 1;
  const int i = static_cast<int>(q) / m - in.probe_n[0], j = static_cast<int>(q) % m - in.probe_n[1];
  return in.center + in.probe_step * (i * in.t1 + j * in.t2);
}

// The probe nearest to a point of the face.
inline std::size_t nearest_probe(const Inlet& in, const V3& p) {
  auto cell = [&](const V3& t, int n) {
    const long i = std::lround(std::clamp((p - in.center).dot(t) / in.probe_step, -1.0 * n, 1.0 * n));
    return static_cast<int>(i) + n;
  };
  return static_cast<std::size_t>(cell(in.t1, in.probe_n[0]) * (2 * in.probe_n[1] + 1) +
                                  cell(in.t2, in.probe_n[1]));
}

// The fluid at the inlets' probes, sampled at the start of each coupling
// window (coupled runs only).
class ProbeFluid {
 public:
  // Every inlet's probe points, inlet after inlet.
  static std::vector<std::array<double, 3>> points(const std::vector<Inlet>& inlets) {
    std::vector<std::array<double, 3>> out;
    for (const Inlet& in : inlets)
      for (std::size_t q = 0; q < probe_count(in); ++q) {
        const V3 x = probe_point(in, q);
        out.push_back({x[0], x[1], x[2]});
      }
    return out;
  }
  static std::size_t count(const std::vector<Inlet>& inlets) {
    std::size_t n = 0;
    for (const Inlet& in : inlets) n += probe_count(in);
    return n;
  }
  // The samples, kFluidValues per probe point (ParticleSolver::set_fluid's
  // rows after the particles'), of the `expected` points this rank asked for.
  void set(std::span<const double> rows, std::size_t expected) {
    if (rows.size() != expected * ParticleSolver::kFluidValues)
      throw std::runtime_error("the fluid sent " +
                               std::to_string(rows.size() / ParticleSolver::kFluidValues) +
                               " samples at the inlets' probes for " + std::to_string(expected) +
                               " probes (a coupling protocol mismatch)");
    samples_.clear();
    for (std::size_t r = 0; r + ParticleSolver::kFluidValues <= rows.size();
         r += ParticleSolver::kFluidValues)
      samples_.push_back(fluid_sample(&rows[r]));
  }
  // What a particle entering through inlet k at `entry` sees: the sample of
  // its nearest probe, or `still` where none was taken (no coupled fluid).
  FluidSample at(const std::vector<Inlet>& inlets, std::size_t k, const V3& entry,
                 const FluidSample& still) const {
    std::size_t first = 0;
    for (std::size_t j = 0; j < k; ++j) first += probe_count(inlets[j]);
    const std::size_t q = first + nearest_probe(inlets[k], entry);
    return q < samples_.size() ? samples_[q] : still;
  }

 private:
  std::vector<FluidSample> samples_;
};

}  // namespace coflow::particles::dpm
