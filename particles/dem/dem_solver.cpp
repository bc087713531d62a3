#include "particles/dem/dem_solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "coflow/log.hpp"
#include "particles/dem/checkpoint.hpp"

#include <tuple>

namespace coflow::particles {

using dem::V3;

DemSolver::DemSolver(const Setup& setup, const Params&) : comm_(setup.comm), params_(setup.params) {
  int size = 1;
  MPI_Comm_size(comm_, &size);
  if (size != 1)
    throw std::runtime_error("dem runs on one rank for now (its MPI decomposition is not written yet): set "
                             "particles.ranks: 1");
  p_ = dem::make_initial(setup.params, setup.cfg);
  s_ = dem::make_setup(setup.params, setup.cfg, p_);
  const std::size_t n = p_.size();
  torque_.assign(3 * n, 0.0);
  fh_.assign(3 * n, 0.0);
  th_.assign(3 * n, 0.0);
  // Cells at least as wide as the farthest interaction: a contact, a bond within
  // its gap, or a bond stretched to its tensile strength.
  double reach = 2.0 * s_.max_radius;
  if (s_.bond_gap >= 0) {
    const double stretch = s_.law.sigma_t * std::pow(2.0 * s_.max_radius, 2) / s_.law.kn;
    reach += std::max(s_.bond_gap, stretch);
  }
  cell_size_ = std::max(reach * 1.01, 1e-12);
  for (int d = 0; d < 3; ++d)
    nc_[d] = std::max(1L, static_cast<long>(std::floor((s_.upper[d] - s_.lower[d]) / cell_size_)));
  const long cells = nc_[0] * nc_[1] * nc_[2];
  neighbours_.resize(cells);
  for (long c = 0; c < cells; ++c) {
    const long cx = c % nc_[0], cy = (c / nc_[0]) % nc_[1], cz = c / (nc_[0] * nc_[1]);
    auto& nb = neighbours_[c];
    for (long dz = -1; dz <= 1; ++dz)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dx = -1; dx <= 1; ++dx) {
          long q[3] = {cx + dx, cy + dy, cz + dz};
          bool ok = true;
          for (int d = 0; d < 3; ++d) {
            if (q[d] >= 0 && q[d] < nc_[d]) continue;
            if (s_.periodic[d])
              q[d] = (q[d] + nc_[d]) % nc_[d];
            else
              ok = false;
          }
          if (ok) nb.push_back((q[2] * nc_[1] + q[1]) * nc_[0] + q[0]);
        }
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  }
  cell_start_.assign(cells + 1, 0);
  // Cement the pairs that touch (within the gap) at the start.
  build_cells();
  long bonds = 0;
  if (s_.bond_gap >= 0)
    for (std::size_t i = 0; i < n; ++i)
      for_candidates(i, [&](std::size_t j) {
        const V3 d = dem::min_image(V3(&p_.x[3 * i]) - V3(&p_.x[3 * j]), s_);
        if (d.norm() - p_.radius[i] - p_.radius[j] <= s_.bond_gap) {
          contacts_[key(p_.id[i], p_.id[j])].bonded = true;
          ++bonds;
        }
      });
  log::info("dem: {} particles, {} bonds, step {:.4g} s, {}x{}x{} cells of {:.4g} m", n, bonds, s_.dt, nc_[0],
            nc_[1], nc_[2], cell_size_);
}

// Counting sort of the particles into cells (buffers reused: no allocation in
// the steady state).
void DemSolver::build_cells() {
  const std::size_t n = p_.size();
  cell_of_.resize(n);
  cell_items_.resize(n);
  std::fill(cell_start_.begin(), cell_start_.end(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    long c[3];
    for (int d = 0; d < 3; ++d) {
      const double t = (p_.x[3 * i + d] - s_.lower[d]) / (s_.upper[d] - s_.lower[d]);
      c[d] = std::clamp(static_cast<long>(std::floor(t * nc_[d])), 0L, nc_[d] - 1);
    }
    cell_of_[i] = (c[2] * nc_[1] + c[1]) * nc_[0] + c[0];
    ++cell_start_[cell_of_[i] + 1];
  }
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  std::vector<long>& fill = candidates_;  // reuse as a cursor array
  fill.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) cell_items_[fill[cell_of_[i]]++] = static_cast<long>(i);
}

// Calls f(j) for every j > i in i's cell and its neighbours, in increasing j:
// the same pair order as dem-reference's double loop.
template <class F>
void DemSolver::for_candidates(std::size_t i, F&& f) {
  thread_local std::vector<long> js;
  js.clear();
  for (long c : neighbours_[cell_of_[i]])
    for (long k = cell_start_[c]; k < cell_start_[c + 1]; ++k)
      if (cell_items_[k] > static_cast<long>(i)) js.push_back(cell_items_[k]);
  std::sort(js.begin(), js.end());
  for (long j : js) f(static_cast<std::size_t>(j));
}

void DemSolver::step(double h) {
  const std::size_t n = p_.size();
  std::fill(p_.force.begin(), p_.force.end(), 0.0);
  std::fill(torque_.begin(), torque_.end(), 0.0);
  crushed_.clear();
  build_cells();
  for (std::size_t i = 0; i < n; ++i)
    for_candidates(i, [&](std::size_t j) {
      const V3 xi(&p_.x[3 * i]), xj(&p_.x[3 * j]);
      const V3 d = dem::min_image(xi - xj, s_);
      const double dist = d.norm();
      const double ri = p_.radius[i], rj = p_.radius[j];
      const double overlap = ri + rj - dist;
      const std::uint64_t k = key(p_.id[i], p_.id[j]);
      auto it = contacts_.find(k);
      if (overlap <= 0.0 && (it == contacts_.end() || !it->second.bonded)) {
        if (it != contacts_.end()) contacts_.erase(it);
        return;
      }
      if (it == contacts_.end()) {
        it = contacts_.emplace(k, dem::ContactState{}).first;
        ++collisions_;
      }
      const V3 nrm = d / dist;
      const double a1 = ri - 0.5 * overlap, a2 = rj - 0.5 * overlap;
      const V3 vi(&p_.v[3 * i]), vj(&p_.v[3 * j]), wi(&p_.w[3 * i]), wj(&p_.w[3 * j]);
      const V3 vrel = (vi + wi.cross(-a1 * nrm)) - (vj + wj.cross(a2 * nrm));
      const dem::ContactForce c = dem::contact_force(nrm, overlap, a1, a2, vrel, ri + rj, it->second, s_.law, h);
      if (c.failure != dem::Failure::none) {
        ++broken_;
        if (c.failure == dem::Failure::compression) {
          crushed_.push_back(i);
          crushed_.push_back(j);
        }
      }
      if (!c.active) {
        contacts_.erase(it);
        return;
      }
      for (int q = 0; q < 3; ++q) {
        p_.force[3 * i + q] += c.force[q];
        p_.force[3 * j + q] -= c.force[q];
        torque_[3 * i + q] += c.torque1[q];
        torque_[3 * j + q] += c.torque2[q];
      }
    });
  // Walls: domain faces, the same law against a plane.
  for (std::size_t i = 0; i < n; ++i)
    for (int f = 0; f < 6; ++f) {
      if (s_.faces[f] != dem::Face::wall) continue;
      const V3 xi(&p_.x[3 * i]);
      const double dist = dem::face_distance(f, xi, s_);
      const double overlap = p_.radius[i] - dist;
      const std::uint64_t k = key(p_.id[i], f);
      auto it = walls_.find(k);
      if (overlap <= 0.0) {
        if (it != walls_.end()) walls_.erase(it);
        continue;
      }
      if (it == walls_.end()) {
        it = walls_.emplace(k, dem::ContactState{}).first;
        ++wall_collisions_;
      }
      const V3 nrm = dem::face_normal(f);
      const V3 vrel = V3(&p_.v[3 * i]) + V3(&p_.w[3 * i]).cross(-dist * nrm);
      dem::ContactLaw law = s_.law;
      law.mu = s_.wall_friction[f];
      const dem::ContactForce c = dem::contact_force(nrm, overlap, dist, 0.0, vrel, 2 * p_.radius[i], it->second, law, h);
      for (int q = 0; q < 3; ++q) {
        p_.force[3 * i + q] += c.force[q];
        torque_[3 * i + q] += c.torque1[q];
      }
    }
  for (std::size_t i : crushed_) {  // grain crushing (seed 000 §2.2.2)
    p_.radius[i] *= 1.0 - s_.crush;
    p_.mass[i] *= std::pow(1.0 - s_.crush, 3);
    p_.inertia[i] = 0.4 * p_.mass[i] * p_.radius[i] * p_.radius[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    V3 x(&p_.x[3 * i]), v(&p_.v[3 * i]), w(&p_.w[3 * i]);
    const V3 force = V3(&p_.force[3 * i]) + V3(&fh_[3 * i]) + p_.mass[i] * s_.gravity;
    const V3 torque = V3(&torque_[3 * i]) + V3(&th_[3 * i]);
    dem::integrate(x, v, w, force, torque, p_.mass[i], p_.inertia[i], s_.alpha, h);
    for (int q = 0; q < 3; ++q) {
      const double L = s_.upper[q] - s_.lower[q];
      if (s_.periodic[q]) x[q] -= L * std::floor((x[q] - s_.lower[q]) / L);
      p_.x[3 * i + q] = x[q];
      p_.v[3 * i + q] = v[q];
      p_.w[3 * i + q] = w[q];
    }
  }
  // Outlets: drop particles whose centre left the box (order kept).
  std::size_t keep = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bool out = false;
    for (int q = 0; q < 3; ++q)
      out = out || (p_.x[3 * i + q] < s_.lower[q] && s_.faces[2 * q] == dem::Face::outlet) ||
            (p_.x[3 * i + q] > s_.upper[q] && s_.faces[2 * q + 1] == dem::Face::outlet);
    if (out) continue;
    if (keep != i) {
      p_.id[keep] = p_.id[i];
      p_.species[keep] = p_.species[i];
      p_.radius[keep] = p_.radius[i];
      p_.mass[keep] = p_.mass[i];
      p_.inertia[keep] = p_.inertia[i];
      for (int q = 0; q < 3; ++q) {
        p_.x[3 * keep + q] = p_.x[3 * i + q];
        p_.v[3 * keep + q] = p_.v[3 * i + q];
        p_.w[3 * keep + q] = p_.w[3 * i + q];
        p_.force[3 * keep + q] = p_.force[3 * i + q];
        fh_[3 * keep + q] = fh_[3 * i + q];
        th_[3 * keep + q] = th_[3 * i + q];
      }
    }
    ++keep;
  }
  if (keep != n) {
    for (auto* a : {&p_.x, &p_.v, &p_.w, &p_.force, &fh_, &th_, &torque_}) a->resize(3 * keep);
    p_.id.resize(keep);
    p_.species.resize(keep);
    p_.radius.resize(keep);
    p_.mass.resize(keep);
    p_.inertia.resize(keep);
  }
  time_ += h;
  ++steps_;
}

void DemSolver::advance(double dt, long substeps) {
  for (long k = 0; k < substeps; ++k) step(dt / substeps);
}

void DemSolver::save(const std::string& dir) {
  std::vector<dem::SavedContact> list;
  for (const auto& [k, c] : contacts_)
    list.push_back({static_cast<std::int64_t>(k >> 32), static_cast<std::int64_t>(k & 0xffffffffu),
                    {c.shear[0], c.shear[1], c.shear[2]}, c.bonded});
  for (const auto& [k, c] : walls_)
    list.push_back({static_cast<std::int64_t>(k >> 32), -1 - static_cast<std::int64_t>(k & 0xffffffffu),
                    {c.shear[0], c.shear[1], c.shear[2]}, c.bonded});
  // Canonical order, so that a checkpoint does not depend on hashing.
  std::sort(list.begin(), list.end(), [](const auto& x, const auto& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
  dem::save_state(comm_, dir, time_, steps_, p_, list);
}

void DemSolver::load(const std::string& dir, long steps, double time) {
  std::vector<dem::SavedContact> list;
  dem::load_state(dir, params_, p_, list);
  contacts_.clear();
  walls_.clear();
  for (const auto& c : list) {
    dem::ContactState st;
    st.shear = V3(c.shear[0], c.shear[1], c.shear[2]);
    st.bonded = c.bonded;
    if (c.b >= 0)
      contacts_[key(c.a, c.b)] = st;
    else
      walls_[key(c.a, -1 - c.b)] = st;
  }
  const std::size_t n = p_.size();
  torque_.assign(3 * n, 0.0);
  fh_.assign(3 * n, 0.0);
  th_.assign(3 * n, 0.0);
  steps_ = steps;
  time_ = time;
}

void DemSolver::set_hydrodynamic(std::span<const double> force, std::span<const double> torque) {
  std::copy(force.begin(), force.end(), fh_.begin());
  std::copy(torque.begin(), torque.end(), th_.begin());
}

ParticleStats DemSolver::stats() {
  double local[6] = {0, 0, 0, 0, 0, 0};
  for (std::size_t i = 0; i < p_.size(); ++i) {
    double v2 = 0, w2 = 0;
    for (int q = 0; q < 3; ++q) {
      local[q] += p_.mass[i] * p_.v[3 * i + q];
      v2 += p_.v[3 * i + q] * p_.v[3 * i + q];
      w2 += p_.w[3 * i + q] * p_.w[3 * i + q];
    }
    local[3] += 0.5 * p_.mass[i] * v2;
    local[5] += 0.5 * p_.inertia[i] * w2;
  }
  local[4] = static_cast<double>(p_.size());
  double global[6];
  MPI_Allreduce(local, global, 6, MPI_DOUBLE, MPI_SUM, comm_);
  long events[3] = {collisions_, wall_collisions_, broken_}, gev[3];
  MPI_Allreduce(events, gev, 3, MPI_LONG, MPI_SUM, comm_);
  collisions_ = wall_collisions_ = 0;  // broken_bonds is cumulative
  ParticleStats st;
  st.momentum = {global[0], global[1], global[2]};
  st.kinetic_energy = global[3];
  st.rotational_energy = global[5];
  st.count = static_cast<long>(global[4]);
  st.collisions = gev[0];
  st.wall_collisions = gev[1];
  st.broken_bonds = gev[2];
  return st;
}

}  // namespace coflow::particles
