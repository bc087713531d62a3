// Pieces both DEM variants use: parameters, wall geometry, the integration of
// one particle, minimum images.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "particles/dem/contact.hpp"
#include "particles/dem/initial.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles::dem {

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
// Variable-size all-to-all of doubles on a communicator: out[r] goes to rank r;
// what every rank sent here lands in `in`, in rank order.
inline void exchange(MPI_Comm comm, std::vector<std::vector<double>>& out, std::vector<double>& in) {
  const int size = static_cast<int>(out.size());
  std::vector<int> sc(size), rc(size), sd(size), rd(size);
  for (int r = 0; r < size; ++r) sc[r] = static_cast<int>(out[r].size());
  MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, comm);
  std::vector<double> flat;
  int ts = 0, tr = 0;
  for (int r = 0; r < size; ++r) {
    sd[r] = ts;
    ts += sc[r];
    rd[r] = tr;
    tr += rc[r];
    flat.insert(flat.end(), out[r].begin(), out[r].end());
  }
  in.resize(tr);
  MPI_Alltoallv(flat.data(), sc.data(), sd.data(), MPI_DOUBLE, in.data(), rc.data(), rd.data(), MPI_DOUBLE, comm);
}

// The rank of `dec` whose block holds position x (clamped into the box).
inline int owner_of(const double* x, const V3& lower, const V3& upper, const coupler::Decomposition& dec) {
  coupler::Index3 c{};
  for (int d = 0; d < 3; ++d) {
    const long cells = dec.cells()[d];
    const double t = (x[d] - lower[d]) / (upper[d] - lower[d]);
    c[d] = std::clamp(static_cast<long>(std::floor(t * cells)), 0L, cells - 1);
  }
  return dec.owner(c);
}

// Whether x, or one of its periodic images, lies within `reach` of the box
// [lo, hi] (the block of another rank): then that rank needs a ghost copy.
inline bool near_block(const double* x, const double* lo, const double* hi, double reach, const V3& lower,
                       const V3& upper, const std::array<bool, 3>& periodic) {
  for (int sx = -1; sx <= 1; ++sx)
    for (int sy = -1; sy <= 1; ++sy)
      for (int sz = -1; sz <= 1; ++sz) {
        const int sh[3] = {sx, sy, sz};
        bool in = true;
        for (int d = 0; d < 3 && in; ++d) {
          if (sh[d] != 0 && !periodic[d]) in = false;
          const double y = x[d] + sh[d] * (upper[d] - lower[d]);
          in = in && y > lo[d] - reach && y < hi[d] + reach;
        }
        if (in) return true;
      }
  return false;
}

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
