// Pieces both DEM variants use: parameters, wall geometry, the integration of
// one particle, minimum images.
#pragma once

#include <fmt/format.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "coflow/reproducible_sum.hpp"
#include "particles/dem/contact.hpp"
#include "particles/dem/initial.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles::dem {

// The count, momentum and energies of the particles of every rank (collective;
// p holds this rank's own). The terms are summed by coupler::reproducible_sums,
// so that 1 rank gives the same bits as N; dem and dpm add their event counts.
inline ParticleStats sum_particles(MPI_Comm comm, const ParticleArrays& p) {
  std::vector<double> terms(5 * p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    double v2 = 0, w2 = 0, *t = &terms[5 * i];
    for (std::size_t q = 0; q < 3; ++q) {
      t[q] = p.mass[i] * p.v[3 * i + q];
      v2 += p.v[3 * i + q] * p.v[3 * i + q];
      w2 += p.w[3 * i + q] * p.w[3 * i + q];
    }
    t[3] = 0.5 * p.mass[i] * v2;
    t[4] = 0.5 * p.inertia[i] * w2;
  }
  const std::vector<double> sums = coupler::reproducible_sums(comm, terms, 5);
  long count = static_cast<long>(p.size());
  MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_LONG, MPI_SUM, comm);
  ParticleStats st;
  st.count = count;
  st.momentum = {sums[0], sums[1], sums[2]};
  st.kinetic_energy = sums[3];
  st.rotational_energy = sums[4];
  return st;
}

struct DemParams {
  void visit(config::Visitor&) {}  // the dem variants use only the common particle keys
};

// Separation vector a - b with the minimum image on periodic axes.
// Both points lie in the box, so |d| < L and one shift at most brings d into
// [-L/2, L/2]. Any setup with periodic, lower and upper (dem, dpm).
template <class Setup>
inline V3 min_image(V3 d, const Setup& s) {
  for (int k = 0; k < 3; ++k)
    if (s.periodic[k]) {
      const double L = s.upper[k] - s.lower[k];
      if (d[k] > 0.5 * L)
        d[k] -= L;
      else if (d[k] < -0.5 * L)
        d[k] += L;
    }
  return d;
}

// The pairs of a bond file, checked against the particles (all of them, as
// made by make_initial): both ids exist, no pair twice, surfaces no farther apart
// than the bond gap. Returned as (smaller id, larger id).
inline std::vector<std::pair<std::int64_t, std::int64_t>> bonds_from_file(const ParticleArrays& a,
                                                                           const DemSetup& s) {
  std::map<std::int64_t, std::size_t> index;
  for (std::size_t n = 0; n < a.size(); ++n) index[a.id[n]] = n;
  std::set<std::pair<std::int64_t, std::int64_t>> seen;
  std::vector<std::pair<std::int64_t, std::int64_t>> out;
  for (const BondPair& b : read_bond_csv(s.bond_file)) {
    const auto pi = index.find(b.i), pj = index.find(b.j);
    if (pi == index.end() || pj == index.end())
      throw std::runtime_error(fmt::format("{}:{}: no particle has id {} (ids run from {} to {})", s.bond_file, b.line,
                                           pi == index.end() ? b.i : b.j, index.empty() ? 0 : index.begin()->first,
                                           index.empty() ? -1 : index.rbegin()->first));
    if (!seen.insert({b.i, b.j}).second)
      throw std::runtime_error(fmt::format("{}:{}: the pair {},{} is listed twice", s.bond_file, b.line, b.i, b.j));
    const std::size_t i = pi->second, j = pj->second;
    const double gap = min_image(V3(&a.x[3 * i]) - V3(&a.x[3 * j]), s).norm() - a.radius[i] - a.radius[j];
    if (gap > s.bond_gap)
      throw std::runtime_error(fmt::format("{}:{}: particles {} and {} are {:.4g} m apart, more than "
                                           "particles.contact.bond.gap = {:.4g} m; raise the gap or drop the pair",
                                           s.bond_file, b.line, b.i, b.j, gap, s.bond_gap));
    out.emplace_back(b.i, b.j);
  }
  return out;
}

// The event log both DEM variants keep (off until enabled): pairs touching for
// the first time and bonds failing.
class EventRecorder {
 public:
  void enable(bool collisions, bool bonds) {
    collisions_ = collisions;
    bonds_ = bonds;
  }
  // n points from j to i; dv = v_i - v_j (centres).
  void collision(double t, std::int64_t i, std::int64_t j, const V3& n, const V3& dv) {
    if (!collisions_) return;
    const double speed = dv.norm(), normal = std::abs(dv.dot(n));
    const double angle = speed > 0.0 ? std::acos(std::min(1.0, normal / speed)) * 180.0 / 3.14159265358979323846 : 0.0;
    log_.collisions.push_back({t, i, j, angle, speed, normal});
  }
  // n: unit normal from the particle into the wall; v: velocity before.
  void impact(double t, std::int64_t id, std::int64_t wall, const V3& point, const V3& n, const V3& v) {
    if (!collisions_) return;
    const double speed = v.norm();
    const double angle = speed > 0.0 ? std::asin(std::min(1.0, std::abs(v.dot(n)) / speed)) * 180.0 / 3.14159265358979323846 : 0.0;
    log_.impacts.push_back({t, id, wall, {point[0], point[1], point[2]}, angle, speed});
  }
  void bond(double t, std::int64_t i, std::int64_t j, const ContactForce& c) {
    if (!bonds_) return;
    const BondFailure mode = c.failure == Failure::tension       ? BondFailure::tension
                             : c.failure == Failure::compression ? BondFailure::compression
                                                                 : BondFailure::shear;
    log_.bonds.push_back({t, i, j, mode, c.failure_normal, c.failure_shear});
  }
  ParticleEvents take() { return std::exchange(log_, {}); }

 private:
  bool collisions_ = false, bonds_ = false;
  ParticleEvents log_;
};

// Inward unit normal and position of a face's plane.
// A contact without a direction: two grains with one centre (an initial
// placement that put two grains in one place), or a centre on a mesh wall (a
// grain passed into it). Both variants stop alike, rather than take a NaN
// normal (the run then blamed the step).
[[noreturn]] inline void coincident_centres(std::int64_t a, std::int64_t b, double t) {
  throw std::runtime_error(
      fmt::format("dem: particles {} and {} have the same centre at t = {:.6g} s: two grains "
                  "were placed in one place (particles.initial), or the step is far too large",
                  a, b, t));
}
[[noreturn]] inline void centre_on_mesh(std::int64_t a, std::size_t mesh, double t) {
  throw std::runtime_error(fmt::format(
      "dem: particle {}'s centre lies on mesh wall {} at t = {:.6g} s: the grain "
      "was placed there (particles.initial) or has passed into the wall (lower particles.time_step)",
      a, mesh + 1, t));
}

inline V3 face_normal(int f) {
  V3 n = V3::Zero();
  n[f / 2] = f % 2 == 0 ? 1.0 : -1.0;
  return n;
}
inline double face_distance(int f, const V3& x, const DemSetup& s) {
  const int a = f / 2;
  return f % 2 == 0 ? x[a] - s.lower[a] : s.upper[a] - x[a];
}

// Central differences with local damping, seed 000 eqs 2.7-2.8 and 2.5:
// velocities at half steps, positions at whole steps.
inline void integrate(V3& x, V3& v, V3& w, const V3& force, const V3& torque, double m, double I, double alpha,
                      double h) {
  for (int k = 0; k < 3; ++k) {
    v[k] += (force[k] + local_damping(alpha, force[k], v[k])) / m * h;
    w[k] += (torque[k] + local_damping(alpha, torque[k], w[k])) / I * h;
  }
  x += v * h;
}

}  // namespace coflow::particles::dem
