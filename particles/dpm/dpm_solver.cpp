#include "particles/dpm/dpm_solver.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "coflow/gather.hpp"
#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/run_config.hpp"
#include "particles/dem/checkpoint.hpp"
#include "particles/dem/initial.hpp"
#include "particles/dpm/state.hpp"

namespace coflow::particles {

using dpm::V3;

static constexpr std::size_t kNone = static_cast<std::size_t>(-1);  // an event's particle not held here

namespace {
V3 at(const std::vector<double>& a, std::size_t i) { return V3(a[3 * i], a[3 * i + 1], a[3 * i + 2]); }
void put(std::vector<double>& a, std::size_t i, const V3& v) {
  for (int k = 0; k < 3; ++k) a[3 * i + k] = v[k];
}
}  // namespace

DpmSolver::DpmSolver(const Setup& setup, const Params&)
    : comm_(setup.comm), params_(setup.params) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  store_.add("diameter", 1, store::migrates, D_);
  store_.add("density", 1, store::migrates, rho_p_);
  store_.add("impulse", 3, store::migrates, impulse_);
  store_.add("fluid", 1, store::migrates, fluid_);
  store_.add("fluctuation", 3, store::migrates, uprime_);
  store_.add("turbulent", 1, store::migrates, turbulent_);
  store_.add("msd_track", dpm::Msd::kTrack, store::migrates, msd_track_);
  msd_ = dpm::Msd(setup.params.dispersion, static_cast<int>(setup.params.species.size()));
  s_ = dpm::make_setup(setup.params, setup.cfg);
  domain_ = store::Domain(setup.decomposition, s_.lower.data(), s_.upper.data(), s_.periodic, comm_);
  wall_impulse_.reset(s_.meshes.size());
  p_ = dem::make_initial(setup.params, setup.cfg);  // every rank makes all, keeps its own
  const std::size_t total = p_.size();
  for (std::int64_t id : p_.id) next_id_ = std::max(next_id_, id + 1);
  p_.force.assign(3 * p_.size(), 0.0);
  if (size_ > 1) {
    set_derived();
    keep_owned();
  }
  set_derived();
  inlets_ = dpm::make_inlets(setup.params, s_.cell, s_.lower, dpm::periods(s_));
  dt_ = s_.auto_step ? stable_step() : s_.dt;
  log::info("dpm: {} particles ({} on this rank), step {:.4g} s ({})", total, p_.size(), dt_,
            s_.auto_step ? "eq. 4.15 at the start" : "given");
}

void DpmSolver::keep_owned() {
  const std::vector<int> owner = domain_.owners(store_);
  std::vector<char> mine(owner.size());
  for (std::size_t i = 0; i < owner.size(); ++i) mine[i] = owner[i] == rank_;
  store_.keep(mine);
}

void DpmSolver::set_derived() {
  const std::size_t n = p_.size();
  D_.resize(n);
  rho_p_.resize(n);
  fluid_.assign(n, s_.still);
  impulse_.assign(3 * n, 0.0);
  uprime_.assign(3 * n, 0.0);
  turbulent_.assign(n, 0);
  msd_track_.assign(dpm::Msd::kTrack * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    D_[i] = 2.0 * p_.radius[i];
    rho_p_[i] = params_.species.at(p_.species[i]).second.density;
  }
}

double DpmSolver::stable_step() const {
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p_.size(); ++i)
    dt = std::min(dt, dpm::lagrangian_step(s_, D_[i], rho_p_[i], at(p_.v, i), fluid_[i]));
  if (s_.collisions)  // tau_c of eq. 4.15
    dt = std::min(dt, 0.2 * dpm::mean_collision_time(
                               p_.size(), [&](std::size_t i) { return at(p_.x, i); },
                               [&](std::size_t i) { return at(p_.v, i); }, [&](std::size_t i) { return D_[i]; }, s_));
  if (size_ > 1) MPI_Allreduce(MPI_IN_PLACE, &dt, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return std::isfinite(dt) ? dt : 1.0;
}

// Pairs that touch within the step: |d| <= (D_i + D_j) / 2 + |u_i - u_j| h at
// the start, so a cell edge of D_max + 2 u_max h puts them in neighbouring cells.
// O(N log N): the sort by cell, then each occupied cell's neighbours by a
// table read (slot_of_, on grids of at most 32 cells a particle) or by walks
// and binary searches over the sorted keys.
void DpmSolver::find_pair_events(double h, std::vector<dpm::Event>& out) {
  const std::size_t n = near_.size(), owned = p_.size();
  if (all_pairs_) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        if (i >= owned && j >= owned) continue;  // two ghosts: their owners see them
        const std::size_t a = near_[i].id < near_[j].id ? i : j, b = a == i ? j : i;
        const V3 d = dpm::min_image(near_[a].x - near_[b].x, s_);
        const double t = dpm::contact_time(d, near_[a].u - near_[b].u, 0.5 * (near_[a].D + near_[b].D), h);
        if (std::isfinite(t)) out.push_back({t, near_[a].id, near_[b].id, a, b});
      }
    return;
  }
  sort_into_cells(h);
  // For a cell off the grid's faces, the neighbours of each (dy, dz) are the
  // keys lo..lo+2 with lo = key + (dz nc_y + dy) nc_x - 1, which grows with the
  // key: one cursor per (dy, dz) walks the sorted keys once per step (binary
  // searches for each of 27 mostly empty cells cost 80 % of a dilute gas's run).
  long cursor[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  long nb[27];
  for (std::size_t c = 0; c < keys_.size(); ++c) {
    const int count = neighbour_cells(c, cursor, nb);
    for (long a = start_[c]; a < start_[c + 1]; ++a) {
      const Packed& pa = packed_[static_cast<std::size_t>(a)];
      for (int m = 0; m < count; ++m)
        for (long b = start_[static_cast<std::size_t>(nb[m])]; b < start_[static_cast<std::size_t>(nb[m]) + 1]; ++b) {
          const Packed& pb = packed_[static_cast<std::size_t>(b)];
          if (pb.id <= pa.id || (pa.index >= owned && pb.index >= owned)) continue;
          // pa has the smaller id: d and dv as dpm-reference forms them.
          const V3 d = dpm::min_image(pa.x - pb.x, s_);
          const double t = dpm::contact_time(d, pa.u - pb.u, 0.5 * (pa.D + pb.D), h);
          if (std::isfinite(t)) out.push_back({t, pa.id, pb.id, pa.index, pb.index});
        }
    }
  }
}

// Cells of edge D_max + 2 u_max h (the same on every rank), stored sparsely:
// particles sorted by cell key into a packed copy (position, trajectory
// velocity, diameter, id, index), occupied cells found by binary search, or
// by a dense key -> slot table where the grid has at most 32 cells a particle
// (4 bytes a cell). The cost does not depend on the box or on how the particles
// cluster (a jet packs thousands into a column a few particles wide).
void DpmSolver::sort_into_cells(double h) {
  const std::size_t n = near_.size();
  double dmax = 0.0, umax = 0.0;
  for (const Near& q : near_) {
    dmax = std::max(dmax, q.D);
    umax = std::max(umax, q.u.norm());
  }
  if (size_ > 1) {
    double m[2] = {dmax, umax};
    MPI_Allreduce(MPI_IN_PLACE, m, 2, MPI_DOUBLE, MPI_MAX, comm_);
    dmax = m[0];
    umax = m[1];
  }
  // No particle on any rank: one cell (a zero edge would divide by 0).
  const double edge = dmax + 2.0 * umax * h;
  for (int k = 0; k < 3; ++k)
    nc_[k] = edge > 0.0
                 ? static_cast<long>(std::clamp((s_.upper[k] - s_.lower[k]) / edge, 1.0, double(1L << 20)))
                 : 1L;
  cell_.resize(n);
  order_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    long c[3];
    for (int k = 0; k < 3; ++k) {
      const double L = s_.upper[k] - s_.lower[k];
      c[k] = std::clamp(static_cast<long>((near_[i].x[k] - s_.lower[k]) / L * nc_[k]), 0L, nc_[k] - 1);
    }
    cell_[i] = (c[2] * nc_[1] + c[1]) * nc_[0] + c[0];
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
    q.x = near_[i].x;
    q.u = near_[i].u;
    q.D = near_[i].D;
    q.id = near_[i].id;
    q.index = i;
    if (keys_.empty() || keys_.back() != cell_[i]) {
      keys_.push_back(cell_[i]);
      start_.push_back(static_cast<long>(r));
    }
  }
  start_.push_back(static_cast<long>(n));
  const long total = nc_[0] * nc_[1] * nc_[2];
  slot_of_.clear();
  if (total > 32 * static_cast<long>(n))
    slot_of_.shrink_to_fit();  // a sparse grid: give the table's memory back
  if (total <= 32 * static_cast<long>(n) &&
      keys_.size() < static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    slot_of_.assign(static_cast<std::size_t>(total), 0);
    for (std::size_t c = 0; c < keys_.size(); ++c)
      slot_of_[static_cast<std::size_t>(keys_[c])] = static_cast<int>(c) + 1;
  }
}

// The occupied neighbour cells (slots in keys_) of occupied cell c, itself
// included; `cursor` carries the walk of inner cells from one cell to the next.
int DpmSolver::neighbour_cells(std::size_t c, long* cursor, long* nb) const {
  const long K = static_cast<long>(keys_.size());
  const long* keys = keys_.data();
  const long nc[3] = {nc_[0], nc_[1], nc_[2]};
  const long key = keys[c];
  const long cc[3] = {key % nc[0], (key / nc[0]) % nc[1], key / (nc[0] * nc[1])};
  const bool small = nc[0] < 3 || nc[1] < 3 || nc[2] < 3;  // neighbours may repeat
  int count = 0;
  bool inner = !small;
  for (int k = 0; k < 3; ++k) inner = inner && cc[k] > 0 && cc[k] < nc[k] - 1;
  const int* dense = slot_of_.empty() ? nullptr : slot_of_.data();
  if (inner && dense) {  // the same slots in the same order as the walk below
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (long k = key + (dz * nc[1] + dy) * nc[0] - 1, e = k + 3; k < e; ++k)
          if (const int s = dense[k]; s > 0) nb[count++] = s - 1;
    return count;
  }
  if (inner) {
    int r = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy, ++r) {
        const long lo = key + (dz * nc[1] + dy) * nc[0] - 1;
        long& at = cursor[r];
        while (at < K && keys[at] < lo) ++at;
        for (long slot = at; slot < K && keys[slot] <= lo + 2; ++slot) nb[count++] = slot;
      }
    return count;
  }
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
        const long k2 = (q[2] * nc[1] + q[1]) * nc[0] + q[0];
        long slot = -1;
        if (dense) {
          slot = dense[k2] - 1;
        } else if (const auto it = std::lower_bound(keys_.begin(), keys_.end(), k2);
                   it != keys_.end() && *it == k2) {
          slot = static_cast<long>(it - keys_.begin());
        }
        if (slot < 0) continue;
        if (!small || std::find(nb, nb + count, slot) == nb + count) nb[count++] = slot;
      }
  return count;
}

// 1. Fluid forces and gravity, RK4 (seed 003 eqs 4.12-4.14), with the
// Langevin fluctuation of the fluid velocity seen (eqs 3.35-3.42).
void DpmSolver::move_freely(double h) {
  const std::size_t n = p_.size();
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
    ranges_.note(p_.species[i], moved_[i].beyond);
    u_[i] = (moved_[i].x - at(p_.x, i)) / h;
  }
}

// 2a. Collisions along the trajectories, earliest first (as dpm-reference):
// the owned particles, then ghosts from the neighbours (several ranks).
void DpmSolver::collect_events(double h) {
  const std::size_t n = p_.size();
  near_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    near_[i] = {at(p_.x, i), u_[i], moved_[i].v, moved_[i].w, D_[i], p_.mass[i], p_.id[i], p_.species[i]};
  if (size_ > 1) add_ghosts(h);
  ev_.clear();
  if (s_.collisions) find_pair_events(h, ev_);
  for (std::size_t i = 0; i < n; ++i) {
    dpm::wall_events(at(p_.x, i), u_[i], D_[i], p_.id[i], i, h, s_, ev_);
    if (!s_.meshes.empty()) dpm::mesh_events(at(p_.x, i), u_[i], D_[i], p_.id[i], i, h, s_, tris_, ev_);
  }
  if (size_ > 1) share_events();  // every rank: all events, indices local (or none)
  std::sort(ev_.begin(), ev_.end());
}

// 2b. Each particle takes its first event here (eqs 4.30-4.31 at walls and
// between particles; the walls on the rest of its path follow in
// after_event); the pair collisions' new velocities replace the free ones.
void DpmSolver::apply_events() {
  const std::size_t n = p_.size();
  hit_.assign(near_.size(), -1.0);
  pair_hit_.assign(near_.size(), 0);
  std::unordered_map<std::int64_t, char> elsewhere;  // ids hit that are not here (several ranks)
  auto taken = [&](std::int64_t id, std::size_t i) {
    return i != kNone ? hit_[i] >= 0.0 : elsewhere.count(id) > 0;
  };
  for (const dpm::Event& e : ev_) {
    if (taken(e.a, e.i) || (e.b >= 0 && taken(e.b, e.j))) continue;
    if (e.b < 0) {
      if (e.i == kNone || e.i >= n) {  // a wall event of a particle owned elsewhere
        if (e.i == kNone)
          elsewhere[e.a] = 1;
        else
          hit_[e.i] = e.t;
        continue;
      }
      V3 nrm, point;
      const dpm::Restitution* law = nullptr;
      dpm::wall_contact(e.b, at(p_.x, e.i), u_[e.i], e.t, D_[e.i], s_, nrm, point, law);
      const V3 before = moved_[e.i].v;
      if (dpm::collide_wall(moved_[e.i].v, moved_[e.i].w, D_[e.i], nrm,
                            *law)) {  // only applied impulses count
        wall_impulse_.add(dpm::wall_slot(e.b), V3(-p_.mass[e.i] * (moved_[e.i].v - before)));
        if (!dpm::mirror_event(e.b, s_)) {  // a symmetry face's mirror is no wall collision
          events_.impact(time_ + e.t, e.a, -1 - e.b, point, nrm, before);
          ++wall_collisions_;
        }
      }
      hit_[e.i] = e.t;
      continue;
    }
    if (e.i == kNone || e.j == kNone) {  // neither is owned here (or only one is known)
      for (auto [id, i] : {std::pair{e.a, e.i}, std::pair{e.b, e.j}}) {
        if (i == kNone)
          elsewhere[id] = 1;
        else
          hit_[i] = e.t;
      }
      continue;
    }
    // Both known here (owned or ghost): every rank holding one of them computes
    // the same collision from the same data and keeps its own particle's part.
    Near& A = near_[e.i];
    Near& B = near_[e.j];
    const V3 d = dpm::min_image((A.x + A.u * e.t) - (B.x + B.u * e.t), s_);
    const V3 nrm = -d.normalized();
    const V3 relative = A.v - B.v;
    const bool applied = dpm::collide_pair(A.v, A.w, A.m, A.D, B.v, B.w, B.m, B.D, nrm, s_.pair_law(A.species, B.species));
    if (applied && e.i < n) {  // the owner of a logs and counts it; only applied impulses count
      events_.collision(time_ + e.t, e.a, e.b, -nrm, relative);
      ++collisions_;
    }
    hit_[e.i] = hit_[e.j] = e.t;
    pair_hit_[e.i] = pair_hit_[e.j] = 1;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (hit_[i] >= 0.0 && pair_hit_[i]) {
      moved_[i].v = near_[i].v;
      moved_[i].w = near_[i].w;
    }
}

// After its event at hit_[i] the particle goes on from the contact with its
// new velocity; walls and meshes on that path take it too (as dpm-reference).
dpm::V3 DpmSolver::after_event(std::size_t i, double h) {
  const double t = hit_[i];
  return dpm::finish_step(at(p_.x, i) + u_[i] * t, moved_[i].v, moved_[i].w, h - t, D_[i], p_.id[i], s_,
                          tris_,
                          [&](double dt, std::int64_t b, const V3& point, const V3& nrm, const V3& before) {
                            wall_impulse_.add(dpm::wall_slot(b), V3(-p_.mass[i] * (moved_[i].v - before)));
                            if (dpm::mirror_event(b, s_)) return;
                            events_.impact(time_ + t + dt, p_.id[i], -1 - b, point, nrm, before);
                            ++wall_collisions_;
                          });
}

// 3. New states (eqs 4.30-4.31 after a collision), then the faces: particles
// that leave through an outlet are dropped, order kept, their impulse kept for
// the fluid at their last position inside.
void DpmSolver::commit_states(double h) {
  const std::size_t n = p_.size();
  std::vector<char> inside(n, 1);
  bool all_inside = true;
  for (std::size_t i = 0; i < n; ++i) {
    V3 x = hit_[i] < 0.0 ? moved_[i].x : after_event(i, h);
    const V3 unwrapped = x;
    if (!dpm::apply_faces(x, s_)) {
      inside[i] = 0;
      all_inside = false;
      const V3 given = at(impulse_, i) + moved_[i].impulse, last = at(p_.x, i);
      departed_.push_back({p_.id[i], {last[0], last[1], last[2]}, {given[0], given[1], given[2]}});
      continue;
    }
    if (msd_.on()) msd_.step(&msd_track_[dpm::Msd::kTrack * i], p_.species[i], at(p_.x, i), unwrapped, time_, h);
    put(p_.x, i, x);
    put(p_.v, i, moved_[i].v);
    put(p_.w, i, moved_[i].w);
    put(impulse_, i, at(impulse_, i) + moved_[i].impulse);
    put(p_.force, i, dpm::fluid_load(seen_[i], D_[i], moved_[i].v, moved_[i].w, s_.forces).force());
  }
  if (!all_inside) store_.keep(inside);
}

void DpmSolver::step(double h) {
  move_freely(h);
  collect_events(h);
  apply_events();
  commit_states(h);
  inject(h);
  if (size_ > 1) domain_.migrate(store_);
  time_ += h;
  ++steps_;
}

// Copies of the owned particles that may touch a particle of another rank
// within the step (within D_max + 2 u_max h of its block, periodic images
// included) go to that rank: id, species, x, u, v, w (after the step), D, m.
void DpmSolver::add_ghosts(double h) {
  const std::size_t n = p_.size();
  double m[2] = {0.0, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    m[0] = std::max(m[0], D_[i]);
    m[1] = std::max(m[1], u_[i].norm());
  }
  MPI_Allreduce(MPI_IN_PLACE, m, 2, MPI_DOUBLE, MPI_MAX, comm_);
  const double reach = m[0] + 2.0 * m[1] * h;
  std::vector<std::vector<double>> out(size_);
  for (std::size_t i = 0; i < n; ++i) {
    for (int r = 0; r < size_; ++r) {
      if (r == rank_) continue;
      if (!domain_.near_block(&p_.x[3 * i], r, reach)) continue;
      const Near& q = near_[i];
      out[r].insert(out[r].end(), {double(q.id), double(q.species), q.x[0], q.x[1], q.x[2], q.u[0], q.u[1], q.u[2],
                                   q.v[0], q.v[1], q.v[2], q.w[0], q.w[1], q.w[2], q.D, q.m});
    }
  }
  std::vector<double> in;
  store::exchange(comm_, out, in);
  constexpr std::size_t G = 16;
  for (std::size_t k = 0; k + G <= in.size(); k += G) {
    const double* g = &in[k];
    near_.push_back({V3(g + 2), V3(g + 5), V3(g + 8), V3(g + 11), g[14], g[15], static_cast<std::int64_t>(g[0]),
                     static_cast<int>(g[1])});
  }
}

// Every rank gets every event of the step (t, a, b; few per step), each once,
// with its particles' local indices (kNone where not held here), so that all
// ranks take the same earliest-first decisions.
void DpmSolver::share_events() {
  std::vector<double> mine;
  mine.reserve(3 * ev_.size());
  for (const dpm::Event& e : ev_) mine.insert(mine.end(), {e.t, double(e.a), double(e.b)});
  const std::vector<double> all = coupler::allgather<double>(comm_, mine, MPI_DOUBLE);
  std::unordered_map<std::int64_t, std::size_t> index;
  for (std::size_t i = 0; i < near_.size(); ++i) index.emplace(near_[i].id, i);
  auto local = [&](std::int64_t id) {
    const auto it = index.find(id);
    return it == index.end() ? kNone : it->second;
  };
  ev_.clear();
  for (std::size_t k = 0; k + 3 <= all.size(); k += 3) {
    const auto a = static_cast<std::int64_t>(all[k + 1]), b = static_cast<std::int64_t>(all[k + 2]);
    const std::size_t i = local(a);
    ev_.push_back({all[k], a, b, i, b < 0 ? i : local(b)});
  }
  std::sort(ev_.begin(), ev_.end());
  ev_.erase(std::unique(ev_.begin(), ev_.end(),
                        [](const dpm::Event& x, const dpm::Event& y) { return x.t == y.t && x.a == y.a && x.b == y.b; }),
            ev_.end());
}

// 4. Inlets (injection.hpp): the particles that entered during the step,
// with the fluid at their inlet's probes.
// With several ranks, rank 0 injects (with the particles near the inlet from
// all ranks) and migration takes the new particles to their owners.
void DpmSolver::inject(double h) {
  for (std::size_t k = 0; k < inlets_.size(); ++k) {
    const dpm::Inlet& in = inlets_[k];
    nearby_.clear();
    std::vector<double> near;
    for (std::size_t i = 0; i < p_.size(); ++i)
      if (dpm::near_inlet(in, h, at(p_.x, i), D_[i])) {
        nearby_.emplace_back(at(p_.x, i), D_[i]);
        near.insert(near.end(), {p_.x[3 * i], p_.x[3 * i + 1], p_.x[3 * i + 2], D_[i]});
      }
    if (size_ > 1) {
      const std::vector<double> all = coupler::gather_to_root<double>(comm_, near, MPI_DOUBLE);
      if (rank_ != 0) continue;
      nearby_.clear();
      for (std::size_t q = 0; q + 4 <= all.size(); q += 4) nearby_.emplace_back(V3(&all[q]), all[q + 3]);
    }
    entering_.clear();
    dpm::inject(inlets_[k], static_cast<int>(k), s_.dispersion.seed, time_, h, nearby_, entering_);
    for (const dpm::Entering& e : entering_) {
      const double m = in.density * std::numbers::pi * e.D * e.D * e.D / 6.0;
      const std::size_t i = store_.append();  // zero w, force, impulse, fluctuation
      p_.id[i] = next_id_++;
      p_.species[i] = e.species;
      put(p_.x, i, e.x);
      put(p_.v, i, e.v);
      p_.radius[i] = 0.5 * e.D;
      p_.mass[i] = m;
      p_.inertia[i] = 0.1 * m * e.D * e.D;
      D_[i] = e.D;
      rho_p_[i] = in.density;
      fluid_[i] = probe_fluid_.at(inlets_, k, e.entry, s_.still);
    }
  }
}

void DpmSolver::advance(double dt, long substeps) {
  const double h = dt / substeps;
  departed_.clear();  // those of the last window, if nobody took them
  for (long n = 0; n < substeps; ++n) {
    const long k = s_.auto_step ? dpm::lagrangian_substeps(s_, h, stable_step()) : 1;  // eq. 4.15 only when automatic
    for (long m = 0; m < k; ++m) step(h / k);
  }
  ranges_.report(comm_, s_.species_names);
}

void DpmSolver::set_hydrodynamic(std::span<const double>, std::span<const double>) {
  throw std::runtime_error("dpm takes the fluid at the particles (immersed.method: point), not forces");
}

void DpmSolver::set_fluid(std::span<const double> samples) {
  if (samples.size() < kFluidValues * p_.size())
    throw std::runtime_error(
        "the fluid sent fewer samples than there are particles (a coupling protocol mismatch)");
  for (std::size_t i = 0; i < p_.size(); ++i) fluid_[i] = dpm::fluid_sample(&samples[kFluidValues * i]);
  probe_fluid_.set(samples.subspan(kFluidValues * p_.size()),
                   rank_ == 0 ? dpm::ProbeFluid::count(inlets_) : 0);
}

// Rank 0 injects (inject), so it alone samples the inlets.
std::vector<std::array<double, 3>> DpmSolver::probe_points() const {
  return rank_ == 0 ? dpm::ProbeFluid::points(inlets_) : std::vector<std::array<double, 3>>{};
}

void DpmSolver::take_impulse(std::vector<double>& impulse) {
  impulse = impulse_;
  std::fill(impulse_.begin(), impulse_.end(), 0.0);
}

void DpmSolver::take_departed(std::vector<DepartedImpulse>& departed) {
  departed.swap(departed_);
  departed_.clear();
}

ParticleStats DpmSolver::stats() {
  ParticleStats st = dem::sum_particles(comm_, p_);
  long counts[2] = {collisions_, wall_collisions_};
  if (size_ > 1) MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_LONG, MPI_SUM, comm_);
  collisions_ = wall_collisions_ = 0;
  st.collisions = counts[0];
  st.wall_collisions = counts[1];
  return st;
}

void DpmSolver::save(const std::string& dir) {
  dem::save_state(comm_, dir, time_, steps_, p_, {}, {collisions_, wall_collisions_, 0});
  if (msd_.on()) save_msd(dir);
  std::vector<double> mine;
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (turbulent_[i]) mine.insert(mine.end(), {double(p_.id[i]), uprime_[3 * i], uprime_[3 * i + 1], uprime_[3 * i + 2]});
  const std::vector<double> all = coupler::gather_to_root<double>(comm_, mine, MPI_DOUBLE);
  if (rank_ != 0) return;  // rank 0 holds the inlets and the next id
  std::map<std::int64_t, dpm::Fluctuation> up;
  for (std::size_t k = 0; k + 4 <= all.size(); k += 4)
    up[static_cast<std::int64_t>(all[k])] = {V3(all[k + 1], all[k + 2], all[k + 3]), true};
  dpm::save_extra(dir, time_, next_id_, inlets_, up);
}

void DpmSolver::write_statistics(const std::string& series_dir) {
  std::vector<std::string> names;
  for (const auto& sp : params_.species) names.push_back(sp.first);
  msd_.write(comm_, series_dir + "/dispersion.csv", names);
}

// The displacement statistics of a checkpoint, dpm_msd.csv: the sums of all
// ranks, then each tracked particle's track by id (17 digits).
void DpmSolver::save_msd(const std::string& dir) const {
  const std::vector<double> totals = msd_.totals(comm_);
  std::vector<double> mine;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    if (msd_track_[dpm::Msd::kTrack * i] == 0) continue;
    mine.push_back(static_cast<double>(p_.id[i]));
    for (int k = 0; k < dpm::Msd::kTrack; ++k) mine.push_back(msd_track_[dpm::Msd::kTrack * i + static_cast<std::size_t>(k)]);
  }
  const std::vector<double> all = coupler::gather_to_root<double>(comm_, mine, MPI_DOUBLE);
  if (rank_ != 0) return;
  std::string out = "totals";
  for (double v : totals) out += fmt::format(",{:.17g}", v);
  out += "\n";
  for (std::size_t q = 0; q + 1 + dpm::Msd::kTrack <= all.size(); q += 1 + dpm::Msd::kTrack) {
    out += fmt::format("track,{}", static_cast<std::int64_t>(all[q]));
    for (int k = 0; k < dpm::Msd::kTrack; ++k)
      out += fmt::format(",{:.17g}", all[q + 1 + static_cast<std::size_t>(k)]);
    out += "\n";
  }
  output::atomic_write(dir + "/dpm_msd.csv", out);
}

void DpmSolver::load_msd(const std::string& dir) {
  std::ifstream in(dir + "/dpm_msd.csv");
  if (!in) throw std::runtime_error(dir + "/dpm_msd.csv is missing: the checkpoint was written without "
                                    "particles.dispersion.msd");
  std::map<std::int64_t, std::vector<double>> tracks;
  std::string line;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string kind, field;
    std::getline(ss, kind, ',');
    std::vector<double> v;
    while (std::getline(ss, field, ',')) v.push_back(config::to_number(field));
    if (kind == "totals" && rank_ == 0) msd_.set_totals(v);
    if (kind == "track" && v.size() == 1 + dpm::Msd::kTrack)
      tracks[static_cast<std::int64_t>(v[0])] = std::vector<double>(v.begin() + 1, v.end());
  }
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (const auto it = tracks.find(p_.id[i]); it != tracks.end())
      for (int k = 0; k < dpm::Msd::kTrack; ++k)
        msd_track_[dpm::Msd::kTrack * i + static_cast<std::size_t>(k)] = it->second[static_cast<std::size_t>(k)];
}

void DpmSolver::load(const std::string& dir, long steps, double time) {
  time_ = time;  // dpm.csv holds the exact clock
  std::vector<dem::SavedContact> contacts;
  dem::EventCounts counts;
  dem::load_state(dir, params_, p_, contacts, &counts);
  if (rank_ != 0) counts = {};  // stats() sums the ranks' counts
  collisions_ = counts.collisions;
  wall_collisions_ = counts.wall_collisions;
  set_derived();
  store_
      .sort_by_id();  // as a straight run holds them (a checkpoint of several ranks lists them rank by rank)
  for (std::int64_t id : p_.id) next_id_ = std::max(next_id_, id + 1);
  if (size_ > 1) keep_owned();
  std::map<std::int64_t, dpm::Fluctuation> up;
  dpm::load_extra(dir, time_, next_id_, inlets_, up);
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (const auto it = up.find(p_.id[i]); it != up.end()) {
      put(uprime_, i, it->second.u);
      turbulent_[i] = it->second.started ? 1 : 0;
    }
  if (msd_.on()) load_msd(dir);
  // The steps taken, as the checkpoint counted them: the windows' sub-steps
  // and eq. 4.15's extra ones (the Langevin draws are keyed by it, so a count
  // from the windows alone would draw used numbers again).
  const long saved = coflow::output::read_step(dir + "/particles.h5");
  steps_ = saved >= 0 ? saved : steps;
}

}  // namespace coflow::particles
