#include "particles/dpm/dpm_solver.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

#include "coflow/log.hpp"
#include "particles/dem/checkpoint.hpp"
#include "particles/dem/initial.hpp"
#include "particles/dpm/state.hpp"

namespace coflow::particles {

using dpm::V3;

namespace {
V3 at(const std::vector<double>& a, std::size_t i) { return V3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }
void put(std::vector<double>& a, std::size_t i, const V3& v) {
  for (int k = 0; k < 3; ++k) a[3 * i + k] = v[k];
}
}  // namespace

DpmSolver::DpmSolver(const Setup& setup, const Params&) : params_(setup.params) {
  int size = 1;
  MPI_Comm_size(setup.comm, &size);
  if (size != 1) throw std::runtime_error("dpm runs on one rank for now: set particles.ranks: 1");
  s_ = dpm::make_setup(setup.params, setup.cfg);
  p_ = dem::make_initial(setup.params, setup.cfg);
  p_.force.assign(3 * p_.size(), 0.0);
  set_derived();
  inlets_ = dpm::make_inlets(setup.params);
  for (std::int64_t id : p_.id) next_id_ = std::max(next_id_, id + 1);
  dt_ = s_.auto_step ? stable_step() : s_.dt;
  log::info("dpm: {} particles, step {:.4g} s ({})", p_.size(), dt_, s_.auto_step ? "eq. 4.15 at the start" : "given");
}

void DpmSolver::set_derived() {
  const std::size_t n = p_.size();
  D_.resize(n);
  rho_p_.resize(n);
  fluid_.assign(n, s_.still);
  impulse_.assign(3 * n, 0.0);
  uprime_.assign(3 * n, 0.0);
  turbulent_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    D_[i] = 2.0 * p_.radius[i];
    rho_p_[i] = params_.species.at(p_.species[i]).second.density;
  }
}

double DpmSolver::stable_step() const {
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p_.size(); ++i)
    dt = std::min(dt, dpm::lagrangian_step(s_, D_[i], rho_p_[i], at(p_.v, i), fluid_[i]));
  return std::isfinite(dt) ? dt : 1.0;
}

// Pairs that touch within the step: |d| <= (D_i + D_j) / 2 + |u_i - u_j| h at
// the start, so a cell edge of D_max + 2 u_max h puts them in neighbouring cells.
// O(N log N): the sort by cell and one binary search per occupied cell and
// neighbour.
void DpmSolver::find_pair_events(const std::vector<V3>& u, double h, std::vector<dpm::Event>& out) {
  const std::size_t n = p_.size();
  auto event = [&](std::size_t i, std::size_t j) {
    const std::size_t a = p_.id[i] < p_.id[j] ? i : j, b = a == i ? j : i;
    const V3 d = dpm::min_image(at(p_.x, a) - at(p_.x, b), s_);
    const double t = dpm::contact_time(d, u[a] - u[b], 0.5 * (D_[a] + D_[b]), h);
    if (std::isfinite(t)) out.push_back({t, p_.id[a], p_.id[b], a, b});
  };
  if (all_pairs_) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) event(i, j);
    return;
  }
  double dmax = 0.0, umax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    dmax = std::max(dmax, D_[i]);
    umax = std::max(umax, u[i].norm());
  }
  // Cells of edge D_max + 2 u_max h, stored sparsely: particles sorted by cell
  // key, occupied cells found by binary search. The cost does not depend on
  // the box or on how the particles cluster (a jet packs thousands into a
  // column a few particles wide).
  const double edge = dmax + 2.0 * umax * h;
  long nc[3];
  for (int k = 0; k < 3; ++k)
    nc[k] = std::max(1L, std::min(1L << 20, static_cast<long>((s_.upper[k] - s_.lower[k]) / edge)));
  const bool small = nc[0] < 3 || nc[1] < 3 || nc[2] < 3;  // neighbours may repeat
  auto key_of = [&](long cx, long cy, long cz) { return (cz * nc[1] + cy) * nc[0] + cx; };
  // Sort by cell into a packed copy (position, trajectory velocity, diameter,
  // id, index), so that the neighbour loops read contiguous memory.
  cell_.resize(n);
  order_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    long c[3];
    for (int k = 0; k < 3; ++k) {
      const double L = s_.upper[k] - s_.lower[k];
      c[k] = std::clamp(static_cast<long>((p_.x[3 * i + k] - s_.lower[k]) / L * nc[k]), 0L, nc[k] - 1);
    }
    cell_[i] = key_of(c[0], c[1], c[2]);
    order_[i] = i;
  }
  std::sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
    return cell_[a] != cell_[b] ? cell_[a] < cell_[b] : a < b;
  });
  packed_.resize(n);
  keys_.clear();
  start_.clear();
  for (std::size_t r = 0; r < n; ++r) {
    const std::size_t i = order_[r];
    Packed& q = packed_[r];
    q.x = at(p_.x, i);
    q.u = u[i];
    q.D = D_[i];
    q.id = p_.id[i];
    q.index = i;
    if (keys_.empty() || keys_.back() != cell_[i]) {
      keys_.push_back(cell_[i]);
      start_.push_back(static_cast<long>(r));
    }
  }
  start_.push_back(static_cast<long>(n));
  long nb[27];
  for (std::size_t c = 0; c < keys_.size(); ++c) {
    const long key = keys_[c];
    const long cc[3] = {key % nc[0], (key / nc[0]) % nc[1], key / (nc[0] * nc[1])};
    int count = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const long o[3] = {dx, dy, dz};
          long q[3];
          bool ok = true;
          for (int k = 0; k < 3; ++k) {
            q[k] = cc[k] + o[k];
            if (q[k] < 0 || q[k] >= nc[k]) {
              if (!s_.periodic[k]) ok = false;
              q[k] = (q[k] + nc[k]) % nc[k];
            }
          }
          if (!ok) continue;
          const long k2 = key_of(q[0], q[1], q[2]);
          const auto it = std::lower_bound(keys_.begin(), keys_.end(), k2);
          if (it == keys_.end() || *it != k2) continue;
          const long slot = static_cast<long>(it - keys_.begin());
          if (!small || std::find(nb, nb + count, slot) == nb + count) nb[count++] = slot;
        }
    for (long a = start_[c]; a < start_[c + 1]; ++a) {
      const Packed& pa = packed_[static_cast<std::size_t>(a)];
      for (int m = 0; m < count; ++m)
        for (long b = start_[static_cast<std::size_t>(nb[m])]; b < start_[static_cast<std::size_t>(nb[m]) + 1]; ++b) {
          const Packed& pb = packed_[static_cast<std::size_t>(b)];
          if (pb.id <= pa.id) continue;
          // pa has the smaller id: d and dv as dpm-reference forms them.
          const V3 d = dpm::min_image(pa.x - pb.x, s_);
          const double t = dpm::contact_time(d, pa.u - pb.u, 0.5 * (pa.D + pb.D), h);
          if (std::isfinite(t)) out.push_back({t, pa.id, pb.id, pa.index, pb.index});
        }
    }
  }
}

void DpmSolver::step(double h) {
  const std::size_t n = p_.size();
  // 1. Fluid forces and gravity, RK4 (seed 003 eqs 4.12-4.14).
  moved_.resize(n);
  u_.resize(n);
  seen_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    seen_[i] = fluid_[i];
    if (s_.dispersion.on) {
      V3 up = at(uprime_, i);
      bool started = turbulent_[i] != 0;
      dpm::langevin_step(up, started, fluid_[i], at(p_.v, i), h, s_.dispersion, p_.id[i], steps_);
      put(uprime_, i, up);
      turbulent_[i] = started ? 1 : 0;
      seen_[i].u += up;
    }
    moved_[i] = dpm::rk4({at(p_.x, i), at(p_.v, i), at(p_.w, i)}, D_[i], p_.mass[i], p_.inertia[i], rho_p_[i],
                         seen_[i], s_, h);
    u_[i] = (moved_[i].x - at(p_.x, i)) / h;
  }
  // 2. Collisions along the trajectories, earliest first (as dpm-reference).
  ev_.clear();
  if (s_.collisions) find_pair_events(u_, h, ev_);
  for (std::size_t i = 0; i < n; ++i) {
    dpm::wall_events(at(p_.x, i), u_[i], D_[i], p_.id[i], i, h, s_, ev_);
    if (!s_.meshes.empty()) dpm::mesh_events(at(p_.x, i), u_[i], D_[i], p_.id[i], i, h, s_, tris_, ev_);
  }
  std::sort(ev_.begin(), ev_.end());
  hit_.assign(n, -1.0);
  for (const dpm::Event& e : ev_) {
    if (hit_[e.i] >= 0.0 || (e.b >= 0 && hit_[e.j] >= 0.0)) continue;
    if (e.b < 0) {
      V3 nrm, point;
      const dpm::Restitution* law = nullptr;
      dpm::wall_contact(e.b, at(p_.x, e.i), u_[e.i], e.t, D_[e.i], s_, nrm, point, law);
      events_.impact(time_ + e.t, e.a, -1 - e.b, point, nrm, moved_[e.i].v);
      dpm::collide_wall(moved_[e.i].v, moved_[e.i].w, D_[e.i], nrm, *law);
      hit_[e.i] = e.t;
      ++wall_collisions_;
      continue;
    }
    const V3 d = dpm::min_image((at(p_.x, e.i) + u_[e.i] * e.t) - (at(p_.x, e.j) + u_[e.j] * e.t), s_);
    const V3 nrm = -d.normalized();
    events_.collision(time_ + e.t, e.a, e.b, -nrm, moved_[e.i].v - moved_[e.j].v);
    dpm::collide_pair(moved_[e.i].v, moved_[e.i].w, p_.mass[e.i], D_[e.i], moved_[e.j].v, moved_[e.j].w,
                      p_.mass[e.j], D_[e.j], nrm, s_.pair_law(p_.species[e.i], p_.species[e.j]));
    hit_[e.i] = hit_[e.j] = e.t;
    ++collisions_;
  }
  // 3. New states (eqs 4.30-4.31 after a collision), then the faces.
  std::size_t keep = 0;
  for (std::size_t i = 0; i < n; ++i) {
    V3 x = hit_[i] < 0.0 ? moved_[i].x : V3(at(p_.x, i) + u_[i] * hit_[i] + moved_[i].v * (h - hit_[i]));
    if (!dpm::apply_faces(x, s_)) continue;
    put(p_.x, keep, x);
    put(p_.v, keep, moved_[i].v);
    put(p_.w, keep, moved_[i].w);
    put(impulse_, keep, at(impulse_, i) + moved_[i].impulse);
    put(p_.force, keep, dpm::fluid_load(seen_[i], D_[i], moved_[i].v, moved_[i].w, s_.forces).force());
    put(uprime_, keep, at(uprime_, i));
    turbulent_[keep] = turbulent_[i];
    p_.id[keep] = p_.id[i];
    p_.species[keep] = p_.species[i];
    p_.radius[keep] = p_.radius[i];
    p_.mass[keep] = p_.mass[i];
    p_.inertia[keep] = p_.inertia[i];
    D_[keep] = D_[i];
    rho_p_[keep] = rho_p_[i];
    fluid_[keep] = fluid_[i];
    ++keep;
  }
  if (keep < n) {
    for (auto* a : {&p_.x, &p_.v, &p_.w, &p_.force, &impulse_, &uprime_}) a->resize(3 * keep);
    turbulent_.resize(keep);
    p_.id.resize(keep);
    p_.species.resize(keep);
    for (auto* a : {&p_.radius, &p_.mass, &p_.inertia, &D_, &rho_p_}) a->resize(keep);
    fluid_.resize(keep);
  }
  inject(h);
  time_ += h;
  ++steps_;
}

// 4. Inlets (injection.hpp): the particles that entered during the step.
void DpmSolver::inject(double h) {
  for (std::size_t k = 0; k < inlets_.size(); ++k) {
    const dpm::Inlet& in = inlets_[k];
    const double reach = dpm::inlet_reach(in, h);
    nearby_.clear();
    for (std::size_t i = 0; i < p_.size(); ++i)
      if ((at(p_.x, i) - in.center).norm() < reach) nearby_.emplace_back(at(p_.x, i), D_[i]);
    entering_.clear();
    dpm::inject(inlets_[k], static_cast<int>(k), s_.dispersion.seed, time_, h, nearby_, entering_);
    for (const dpm::Entering& e : entering_) {
      const double m = in.density * std::numbers::pi * e.D * e.D * e.D / 6.0;
      p_.id.push_back(next_id_++);
      p_.species.push_back(e.species);
      for (int c = 0; c < 3; ++c) {
        p_.x.push_back(e.x[c]);
        p_.v.push_back(e.v[c]);
        p_.w.push_back(0.0);
        p_.force.push_back(0.0);
        impulse_.push_back(0.0);
        uprime_.push_back(0.0);
      }
      p_.radius.push_back(0.5 * e.D);
      p_.mass.push_back(m);
      p_.inertia.push_back(0.1 * m * e.D * e.D);
      D_.push_back(e.D);
      rho_p_.push_back(in.density);
      fluid_.push_back(s_.still);
      turbulent_.push_back(0);
    }
  }
}

void DpmSolver::advance(double dt, long substeps) {
  const double h = dt / substeps;
  for (long n = 0; n < substeps; ++n) {
    const long k = dpm::lagrangian_substeps(s_, h, stable_step());
    for (long m = 0; m < k; ++m) step(h / k);
  }
}

void DpmSolver::set_hydrodynamic(std::span<const double>, std::span<const double>) {
  throw std::runtime_error("dpm takes the fluid at the particles (immersed.method: point), not forces");
}

void DpmSolver::set_fluid(std::span<const double> samples) {
  for (std::size_t i = 0; i < p_.size(); ++i) {
    const double* s = &samples[kFluidValues * i];
    fluid_[i] = {V3(s), V3(s + 3), s[6], s[7], s[8], s[9]};
  }
}

void DpmSolver::take_impulse(std::vector<double>& impulse) {
  impulse = impulse_;
  std::fill(impulse_.begin(), impulse_.end(), 0.0);
}

ParticleStats DpmSolver::stats() {
  ParticleStats st;
  st.count = static_cast<long>(p_.size());
  for (std::size_t i = 0; i < p_.size(); ++i) {
    const V3 v = at(p_.v, i), w = at(p_.w, i);
    for (int k = 0; k < 3; ++k) st.momentum[k] += p_.mass[i] * v[k];
    st.kinetic_energy += 0.5 * p_.mass[i] * v.squaredNorm();
    st.rotational_energy += 0.5 * p_.inertia[i] * w.squaredNorm();
  }
  st.collisions = collisions_;
  st.wall_collisions = wall_collisions_;
  collisions_ = wall_collisions_ = 0;
  return st;
}

void DpmSolver::save(const std::string& dir) {
  dem::save_state(MPI_COMM_SELF, dir, time_, steps_, p_, {});
  std::map<std::int64_t, dpm::Fluctuation> up;
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (turbulent_[i]) up[p_.id[i]] = {at(uprime_, i), true};
  dpm::save_extra(dir, time_, next_id_, inlets_, up);
}

void DpmSolver::load(const std::string& dir, long steps, double time) {
  time_ = time;  // dpm.csv holds the exact clock
  std::vector<dem::SavedContact> contacts;
  dem::load_state(dir, params_, p_, contacts);
  set_derived();
  for (std::int64_t id : p_.id) next_id_ = std::max(next_id_, id + 1);
  std::map<std::int64_t, dpm::Fluctuation> up;
  dpm::load_extra(dir, time_, next_id_, inlets_, up);
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (const auto it = up.find(p_.id[i]); it != up.end()) {
      put(uprime_, i, it->second.u);
      turbulent_[i] = it->second.started ? 1 : 0;
    }
  steps_ = steps;
}

}  // namespace coflow::particles
