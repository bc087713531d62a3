#include "particles/dem/dem_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "particles/dem/checkpoint.hpp"

namespace coflow::particles {

using dem::V3;

DemSolver::DemSolver(const Setup& setup, const Params&)
    : comm_(setup.comm), params_(setup.params) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  store_.add("torque", 3, store::stays, torque_);
  store_.add("hydrodynamic_force", 3, store::migrates, fh_);
  store_.add("hydrodynamic_torque", 3, store::migrates, th_);
  store_.add("owned", 1, store::migrates, owned_);
  p_ = dem::make_initial(setup.params, setup.cfg);
  s_ = dem::make_setup(setup.params, setup.cfg, p_);
  domain_ = store::Domain(setup.decomposition, s_.lower.data(), s_.upper.data(), s_.periodic, comm_);
  wall_impulse_.reset(s_.meshes.size());
  const std::size_t n = p_.size();
  torque_.assign(3 * n, 0.0);
  fh_.assign(3 * n, 0.0);
  th_.assign(3 * n, 0.0);
  // Cells at least as wide as the farthest interaction: a contact, a bond within
  // its gap, or a bond stretched to its tensile strength.
  // The neighbour list keeps the pairs within that reach plus a skin, and is
  // rebuilt once a particle has moved half the skin (on one rank; with MPI the
  // ghosts change every step and so does the list).
  // Crushing (seed 000 §2.2.2) shrinks radii, not the distance between
  // centres: a bond not yet failed stays within 2 R_max + extra_ of its
  // partner, inside the ghost reach; build_list keeps it listed beyond the
  // cut of the shrunk radii (far_bonds), so its tension failure is seen.
  if (s_.bond_gap >= 0) {
    const double stretch = s_.law.sigma_t * std::pow(2.0 * s_.max_radius, 2) / s_.law.kn;
    extra_ = std::max(s_.bond_gap, stretch);
  }
  skin_ = 0.1 * s_.max_radius;
  const double reach = 2.0 * s_.max_radius + extra_ + skin_;
  // No particle at all: one cell (cells as narrow as a bond's gap alone would overflow the count).
  cell_size_ =
      s_.max_radius > 0.0
          ? reach * 1.01
          : std::max({s_.upper[0] - s_.lower[0], s_.upper[1] - s_.lower[1], s_.upper[2] - s_.lower[2]});
  for (int d = 0; d < 3; ++d)
    nc_[d] = std::max(1L, static_cast<long>(std::floor((s_.upper[d] - s_.lower[d]) / cell_size_)));
  // Every rank made every particle (deterministically): it keeps the owned
  // ones, and the bonds and histories that involve them.
  owned_.assign(n, 1);
  if (size_ > 1)
    for (std::size_t i = 0; i < n; ++i) owned_[i] = domain_.owner_of(&p_.x[3 * i]) == rank_;
  // Cement the pairs that touch (within the gap) at the start: every rank
  // counts them all (for the log) but holds only those of its particles.
  // (Every rank holds every particle here: its cells span them all, only for
  // this.)
  long bonds = 0;
  auto bond = [&](std::size_t i, std::size_t j) {
    ++bonds;
    if (owned_[i] || owned_[j]) contacts_[key(p_.id[i], p_.id[j])].bonded = true;
  };
  if (!s_.bond_file.empty()) {
    std::unordered_map<std::int64_t, std::size_t> index;
    for (std::size_t i = 0; i < n; ++i) index[p_.id[i]] = i;
    for (const auto& [a, b] : dem::bonds_from_file(p_, s_)) bond(index.at(a), index.at(b));
  } else if (s_.bond_gap >= 0) {
    build_cells();
    for (std::size_t i = 0; i < n; ++i)
      for_candidates(i, [&](std::size_t j) {
        const V3 d = dem::min_image(V3(&p_.x[3 * i]) - V3(&p_.x[3 * j]), s_);
        if (d.norm() - p_.radius[i] - p_.radius[j] <= s_.bond_gap) bond(i, j);
      });
  }
  if (size_ > 1) drop_ghosts();
  log::info("dem: {} particles ({} on this rank), {} bonds, step {:.4g} s, {}x{}x{} cells of {:.4g} m", n, p_.size(),
            bonds, s_.dt, nc_[0], nc_[1], nc_[2], cell_size_);
}

void DemSolver::add_ghosts() {
  store_.unpack_all(domain_.send_ghosts(store_, cell_size_), store::ghosts);  // owned_ 0
  store_.sort_by_id();
}

void DemSolver::drop_ghosts() {
  invalidate_list();  // local indices change
  store_.keep(owned_);
  // Histories that no longer involve a particle of this rank (grains gone
  // through an outlet take theirs along in drop_outlets).
  if (size_ > 1) {
    std::unordered_map<std::int64_t, char> mine;
    for (auto id : p_.id) mine[id] = 1;
    for (auto it = contacts_.begin(); it != contacts_.end();)
      it = (!mine.count(static_cast<std::int64_t>(it->first >> 32)) &&
            !mine.count(static_cast<std::int64_t>(it->first & 0xffffffffu)))
               ? contacts_.erase(it)
               : std::next(it);
    for (auto it = walls_.begin(); it != walls_.end();)
      it = !mine.count(static_cast<std::int64_t>(it->first >> 32)) ? walls_.erase(it) : std::next(it);
  }
}

void DemSolver::migrate() {
  invalidate_list();  // local indices change
  const std::vector<int> owner = domain_.owners(store_);
  const std::vector<double> received = domain_.send_leavers(store_, owner);
  std::unordered_map<std::int64_t, int> leaving;  // id -> new owner
  for (std::size_t i = 0; i < owner.size(); ++i)
    if (owner[i] != rank_) {
      leaving[p_.id[i]] = owner[i];
      owned_[i] = 0;
    }
  // Contact histories travel with the particles that leave: the pair (a
  // partner < 0: -1 - the wall's key), the spring, the bond, the direction.
  constexpr std::size_t kRow = 9;
  std::vector<std::vector<double>> hist(size_);
  const auto send = [&](int to, double a, double b, const dem::ContactState& c) {
    hist[to].insert(hist[to].end(), {a, b, c.shear[0], c.shear[1], c.shear[2], double(c.bonded), c.normal[0],
                                     c.normal[1], c.normal[2]});
  };
  for (const auto& [k, c] : contacts_)
    for (const std::int64_t id : {static_cast<std::int64_t>(k >> 32), static_cast<std::int64_t>(k & 0xffffffffu)}) {
      auto it = leaving.find(id);
      if (it != leaving.end()) send(it->second, double(k >> 32), double(k & 0xffffffffu), c);
    }
  for (const auto& [k, c] : walls_) {
    auto it = leaving.find(static_cast<std::int64_t>(k >> 32));
    if (it != leaving.end()) send(it->second, double(k >> 32), -1.0 - double(k & 0xffffffffu), c);
  }
  std::vector<double> in;
  store::exchange(comm_, hist, in);
  drop_ghosts();  // drops the leavers (and histories no particle here needs)
  store_.unpack_all(received, store::migrates);  // owned_ 1
  for (std::size_t k = 0; k + kRow <= in.size(); k += kRow) {
    dem::ContactState st;
    st.shear = V3(in[k + 2], in[k + 3], in[k + 4]);
    st.bonded = in[k + 5] != 0;
    st.normal = V3(in[k + 6], in[k + 7], in[k + 8]);
    const auto a = static_cast<std::int64_t>(in[k]);
    if (in[k + 1] >= 0)
      contacts_.emplace(key(a, static_cast<std::int64_t>(in[k + 1])), st);
    else
      walls_.emplace(key(a, static_cast<std::int64_t>(-1 - in[k + 1])), st);
  }
  store_.sort_by_id();
}

// Counting sort of the particles into cells (buffers reused: no allocation in
// the steady state).
void DemSolver::sync_contacts() {
  contacts_.clear();
  for (std::size_t i = 0; i + 1 < list_start_.size(); ++i)
    for (long k = list_start_[i]; k < list_start_[i + 1]; ++k)
      if (list_live_[k]) contacts_.emplace(key(p_.id[i], p_.id[list_items_[k]]), list_state_[k]);
}

void DemSolver::invalidate_list() {
  if (list_valid_) sync_contacts();
  list_valid_ = false;
}

// Bonded pairs (i < j) farther apart than the list's cut, sorted: a crushed
// grain's other bonds (their gaps widen as its radius shrinks). They stay
// listed while both particles are on this rank, so that their tension failure
// is seen, counted and logged as dem-reference sees it (its every pair).
std::vector<std::pair<long, long>> DemSolver::far_bonds() const {
  std::vector<std::pair<long, long>> far;
  const auto index = [&](std::int64_t id) -> long {
    const auto it = std::lower_bound(p_.id.begin(), p_.id.end(), id);
    return it != p_.id.end() && *it == id ? static_cast<long>(it - p_.id.begin()) : -1;
  };
  for (const auto& [k, c] : contacts_) {
    if (!c.bonded) continue;
    const long a = index(static_cast<std::int64_t>(k >> 32)),
               b = index(static_cast<std::int64_t>(k & 0xffffffffu));
    if (a < 0 || b < 0) continue;
    const auto i = static_cast<std::size_t>(std::min(a, b)), j = static_cast<std::size_t>(std::max(a, b));
    if (!owned_[i] && !owned_[j]) continue;
    const double cut = p_.radius[i] + p_.radius[j] + extra_ + skin_;
    if (dem::min_image(V3(&p_.x[3 * i]) - V3(&p_.x[3 * j]), s_).squaredNorm() >= cut * cut)
      far.emplace_back(static_cast<long>(i), static_cast<long>(j));
  }
  std::sort(far.begin(), far.end());
  return far;
}

void DemSolver::build_list() {
  if (list_valid_) sync_contacts();
  build_cells();
  const std::size_t n = p_.size();
  const std::vector<std::pair<long, long>> far = far_bonds();  // usually none
  auto next_far = far.begin();
  list_start_.assign(n + 1, 0);
  list_items_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const V3 xi(&p_.x[3 * i]);
    const std::size_t first = list_items_.size();
    for_candidates(i, [&](std::size_t j) {
      if (!owned_[i] && !owned_[j]) return;
      const double cut = p_.radius[i] + p_.radius[j] + extra_ + skin_;
      if (dem::min_image(xi - V3(&p_.x[3 * j]), s_).squaredNorm() < cut * cut)
        list_items_.push_back(static_cast<long>(j));
    });
    if (next_far != far.end() && next_far->first == static_cast<long>(i)) {
      for (; next_far != far.end() && next_far->first == static_cast<long>(i); ++next_far)
        list_items_.push_back(next_far->second);
      // in increasing j with the others: dem-reference's pair order
      std::sort(list_items_.begin() + static_cast<long>(first), list_items_.end());
    }
    list_start_[i + 1] = static_cast<long>(list_items_.size());
  }
  // Histories move from the map into the list; the map is rebuilt from the list
  // whenever it is needed (migration, checkpoints, the next build).
  list_state_.assign(list_items_.size(), dem::ContactState{});
  list_live_.assign(list_items_.size(), 0);
  for (std::size_t i = 0; i < n; ++i)
    for (long k = list_start_[i]; k < list_start_[i + 1]; ++k) {
      const auto it = contacts_.find(key(p_.id[i], p_.id[list_items_[k]]));
      if (it == contacts_.end()) continue;
      list_state_[k] = it->second;
      list_live_[k] = 1;
    }
  contacts_.clear();
  list_x_ = p_.x;
  list_valid_ = true;
  ++list_builds_;
}

bool DemSolver::list_stale() const {
  // Two particles approach by at most the sum of their displacements.
  const double half = 0.5 * skin_;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    const V3 d = dem::min_image(V3(&p_.x[3 * i]) - V3(&list_x_[3 * i]), s_);
    if (d.squaredNorm() > half * half) return true;
  }
  return false;
}

// The cells hold the particles on this rank only (owned and ghosts): a window
// of the global grid around them, one empty cell beyond them on every side,
// so that its memory and the sweep over it follow the rank's block, not the
// domain. Along a periodic axis the window is taken around the first
// particle's cell (a block's particles and ghosts lie in one run of cells,
// its periodic images next to it); where it would reach round the axis it is
// the whole axis, whose neighbours wrap.
void DemSolver::build_cells() {
  const std::size_t n = p_.size();
  cell_of_.resize(n);
  cell_items_.resize(n);
  std::vector<long>& at = candidates_;  // the particles' global cells, then local
  at.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      const double t = (p_.x[3 * i + d] - s_.lower[d]) / (s_.upper[d] - s_.lower[d]);
      at[3 * i + d] = std::clamp(static_cast<long>(std::floor(t * nc_[d])), 0L, nc_[d] - 1);
    }
  for (int d = 0; d < 3; ++d) window_axis(d, at);
  for (std::size_t i = 0; i < n; ++i)
    cell_of_[i] = (at[3 * i + 2] * win_n_[1] + at[3 * i + 1]) * win_n_[0] + at[3 * i];
  // A window mostly empty (a dilute rank, or the start's whole box): the
  // particles sorted by cell, a cell found by bisection, memory by particle.
  const long volume = win_n_[0] * win_n_[1] * win_n_[2];
  sparse_ = volume > 8 * static_cast<long>(n) + 4096;
  if (sparse_) {
    std::vector<long>().swap(cell_start_);
    for (std::size_t i = 0; i < n; ++i) cell_items_[i] = static_cast<long>(i);
    std::sort(cell_items_.begin(), cell_items_.end(),
              [&](long a, long b) {  // a cell's order: for_candidates sorts
                return cell_of_[static_cast<std::size_t>(a)] < cell_of_[static_cast<std::size_t>(b)];
              });
    sorted_cells_.resize(n);
    for (std::size_t k = 0; k < n; ++k) sorted_cells_[k] = cell_of_[static_cast<std::size_t>(cell_items_[k])];
    return;
  }
  std::fill(cell_start_.begin(), cell_start_.end(), 0);
  cell_start_.resize(static_cast<std::size_t>(volume + 1), 0);
  for (std::size_t i = 0; i < n; ++i) ++cell_start_[cell_of_[i] + 1];
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  std::vector<long>& fill = candidates_;  // reuse as a cursor array
  fill.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) cell_items_[fill[cell_of_[i]]++] = static_cast<long>(i);
}

// build_cells' window along axis d: `at`'s global cells (stride 3) become
// local ones in place, and win_n_[d] and win_wrap_[d] are set.
void DemSolver::window_axis(int d, std::vector<long>& at) {
  const std::size_t n = at.size() / 3;
  const long nc = nc_[d], anchor = n > 0 ? at[static_cast<std::size_t>(d)] : 0;
  long lo = 0, hi = -1;  // the particles' cells relative to the anchor (periodic: the nearest image)
  for (std::size_t i = 0; i < n; ++i) {
    long r = at[3 * i + d] - anchor;
    if (s_.periodic[d]) r = r < -nc / 2 ? r + nc : r >= nc - nc / 2 ? r - nc : r;
    at[3 * i + d] = r;
    lo = i == 0 ? r : std::min(lo, r);
    hi = i == 0 ? r : std::max(hi, r);
  }
  win_wrap_[d] = s_.periodic[d] && hi - lo + 3 > nc;
  win_n_[d] = win_wrap_[d] ? nc : std::max(1L, hi - lo + 3);
  for (std::size_t i = 0; i < n; ++i) {
    long& r = at[3 * i + d];
    r = win_wrap_[d] ? ((r + anchor) % nc + nc) % nc : r - lo + 1;
  }
}

// Calls f(j) for every j > i in i's cell and its neighbours, in increasing j:
// the same pair order as dem-reference's double loop. (On an axis of fewer
// than three cells that wraps, a neighbour cell comes more than once: its
// particles are taken once.)
template <class F>
void DemSolver::for_candidates(std::size_t i, F&& f) {
  thread_local std::vector<long> js;
  js.clear();
  const long c = cell_of_[i];
  const long l[3] = {c % win_n_[0], (c / win_n_[0]) % win_n_[1], c / (win_n_[0] * win_n_[1])};
  for (long dz = -1; dz <= 1; ++dz)
    for (long dy = -1; dy <= 1; ++dy)
      for (long dx = -1; dx <= 1; ++dx) {
        long q[3] = {l[0] + dx, l[1] + dy, l[2] + dz};
        bool inside = true;
        for (int d = 0; d < 3; ++d) {
          if (win_wrap_[d]) q[d] = (q[d] + win_n_[d]) % win_n_[d];
          inside = inside && q[d] >= 0 && q[d] < win_n_[d];  // an axis of one cell: its window is the cell
        }
        if (!inside) continue;
        const long cell = (q[2] * win_n_[1] + q[1]) * win_n_[0] + q[0];
        long k = 0, end = 0;
        if (sparse_) {
          const auto [a, b] = std::equal_range(sorted_cells_.begin(), sorted_cells_.end(), cell);
          k = a - sorted_cells_.begin(), end = b - sorted_cells_.begin();
        } else {
          k = cell_start_[cell], end = cell_start_[cell + 1];
        }
        for (; k < end; ++k)
          if (cell_items_[k] > static_cast<long>(i)) js.push_back(cell_items_[k]);
      }
  std::sort(js.begin(), js.end());
  js.erase(std::unique(js.begin(), js.end()), js.end());
  for (long j : js) f(static_cast<std::size_t>(j));
}

// One listed pair (i, j) with its history in list_state_[k] while
// list_live_[k] (touching or bonded), as dem-reference keeps it in its map.
void DemSolver::pair_contact(std::size_t i, std::size_t j, long k, double h) {
  const V3 xi(&p_.x[3 * i]), xj(&p_.x[3 * j]);
  const V3 d = dem::min_image(xi - xj, s_);
  const double dist = d.norm();
  const double ri = p_.radius[i], rj = p_.radius[j];
  const double overlap = ri + rj - dist;
  dem::ContactState& state = list_state_[k];
  if (overlap <= 0.0 && (!list_live_[k] || !state.bonded)) {
    list_live_[k] = 0;  // apart and not cemented: the history ends
    return;
  }
  if (!list_live_[k]) {
    list_live_[k] = 1;
    state = dem::ContactState{};
    if (owned_[i]) {  // each pair counted once: by the owner of its smaller id
      ++collisions_;
      events_.collision(time_, p_.id[i], p_.id[j], d / dist, V3(&p_.v[3 * i]) - V3(&p_.v[3 * j]));
    }
  }
  if (dist == 0.0) dem::coincident_centres(p_.id[i], p_.id[j], time_);  // (NaN: the state check's)
  const V3 nrm = d / dist;
  const double a1 = ri - 0.5 * overlap, a2 = rj - 0.5 * overlap;
  const V3 vi(&p_.v[3 * i]), vj(&p_.v[3 * j]), wi(&p_.w[3 * i]), wj(&p_.w[3 * j]);
  const V3 vrel = (vi + wi.cross(-a1 * nrm)) - (vj + wj.cross(a2 * nrm));
  const dem::ContactForce c = dem::contact_force(nrm, overlap, a1, a2, vrel, ri + rj, state, s_.law, h);
  if (c.failure != dem::Failure::none) {
    if (owned_[i]) {
      ++broken_;
      events_.bond(time_, p_.id[i], p_.id[j], c);
    }
    if (c.failure == dem::Failure::compression) {
      if (owned_[i]) crushed_.push_back(i);
      if (owned_[j]) crushed_.push_back(j);
    }
  }
  if (!c.active) {
    list_live_[k] = 0;
    return;
  }
  for (int q = 0; q < 3; ++q) {
    if (owned_[i]) {
      p_.force[3 * i + q] += c.force[q];
      torque_[3 * i + q] += c.torque1[q];
    }
    if (owned_[j]) {
      p_.force[3 * j + q] -= c.force[q];
      torque_[3 * j + q] += c.torque2[q];
    }
  }
}

// Walls: domain faces, the same law against a plane.
void DemSolver::face_contacts(double h) {
  const std::size_t n = p_.size();
  std::array<int, 6> wall_faces{};
  int nwalls = 0;
  for (int f = 0; f < 6; ++f)
    if (s_.faces[f] == dem::Face::wall) wall_faces[nwalls++] = f;
  for (std::size_t i = 0; i < n && nwalls > 0; ++i)
    for (int fi = 0; fi < nwalls; ++fi) {
      const int f = wall_faces[fi];
      if (!owned_[i]) continue;
      const V3 xi(&p_.x[3 * i]);
      const double dist = dem::face_distance(f, xi, s_);
      const double overlap = p_.radius[i] - dist;
      if (overlap <= 0.0) continue;  // a history it had is swept below
      const std::uint64_t k = key(p_.id[i], f);
      auto it = walls_.find(k);
      if (it == walls_.end()) {
        it = walls_.emplace(k, dem::ContactState{}).first;
        ++wall_collisions_;
      }
      it->second.seen = steps_;
      const V3 nrm = dem::face_normal(f);
      const V3 vrel = V3(&p_.v[3 * i]) + V3(&p_.w[3 * i]).cross(-dist * nrm);
      dem::ContactLaw law = s_.law;
      law.mu = s_.wall_friction[f];
      const dem::ContactForce c = dem::contact_force(nrm, overlap, dist, 0.0, vrel, 2 * p_.radius[i], it->second, law, h);
      for (int q = 0; q < 3; ++q) {
        p_.force[3 * i + q] += c.force[q];
        torque_[3 * i + q] += c.torque1[q];
      }
      wall_impulse_.add(static_cast<std::size_t>(f), V3(-h * c.force));
    }
}

// Triangle-mesh walls: the same law against the closest point of each
// triangle touched (FCL's hierarchy finds the candidates).
void DemSolver::mesh_contacts(double h) {
  const std::size_t n = p_.size();
  for (std::size_t i = 0; i < n && !s_.meshes.empty(); ++i) {
    if (!owned_[i]) continue;
    const V3 xi(&p_.x[3 * i]);
    for (std::size_t m = 0; m < s_.meshes.size(); ++m) {
      s_.meshes[m].contacts(xi, p_.radius[i], mesh_hits_);
      for (const auto& hit : mesh_hits_) {
        const V3 d = xi - hit.point;
        const double dist = d.norm();
        if (dist == 0.0) dem::centre_on_mesh(p_.id[i], m, time_);
        const V3 nrm = d / dist;
        const int slot = dem::mesh_history_slot(nrm, steps_, [&](int k) -> const dem::ContactState* {
          auto f = walls_.find(key(p_.id[i], dem::mesh_wall_key(m, k)));
          return f == walls_.end() ? nullptr : &f->second;
        });
        const std::uint64_t k = key(p_.id[i], dem::mesh_wall_key(m, slot));
        auto it = walls_.find(k);
        if (it == walls_.end()) {
          it = walls_.emplace(k, dem::ContactState{}).first;
          ++wall_collisions_;
        }
        it->second.seen = steps_;
        it->second.normal = nrm;
        const V3 vrel = V3(&p_.v[3 * i]) + V3(&p_.w[3 * i]).cross(-dist * nrm);
        dem::ContactLaw law = s_.law;
        law.mu = s_.meshes[m].friction();
        const dem::ContactForce c =
            dem::contact_force(nrm, p_.radius[i] - dist, dist, 0.0, vrel, 2 * p_.radius[i], it->second, law, h);
        for (int q = 0; q < 3; ++q) {
          p_.force[3 * i + q] += c.force[q];
          torque_[3 * i + q] += c.torque1[q];
        }
        wall_impulse_.add(6 + m, V3(-h * c.force));
      }
    }
  }
}

// Grain crushing (seed 000 §2.2.2): a grain whose bond failed in compression
// loses a fraction of its radius.
void DemSolver::crush_grains() {
  for (std::size_t i : crushed_) {
    p_.radius[i] *= 1.0 - s_.crush;
    p_.mass[i] *= std::pow(1.0 - s_.crush, 3);
    p_.inertia[i] = 0.4 * p_.mass[i] * p_.radius[i] * p_.radius[i];
  }
}

// The owned, free particles move (seed 000 eqs 2.3-2.10: leapfrog, with local damping),
// wrapped on periodic axes.
void DemSolver::integrate_owned(double h) {
  const std::size_t n = p_.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!owned_[i]) continue;
    V3 x(&p_.x[3 * i]), v(&p_.v[3 * i]), w(&p_.w[3 * i]);
    const V3 force = V3(&p_.force[3 * i]) + V3(&fh_[3 * i]) + p_.mass[i] * s_.gravity;
    const V3 torque = V3(&torque_[3 * i]) + V3(&th_[3 * i]);
    if (s_.fixed[p_.species[i]]) continue;
    dem::integrate(x, v, w, force, torque, p_.mass[i], p_.inertia[i], s_.alpha, h);
    for (int q = 0; q < 3; ++q) {
      const double L = s_.upper[q] - s_.lower[q];
      if (s_.periodic[q]) {  // a particle moves far less than a box length per step
        if (x[q] < s_.lower[q])
          x[q] += L;
        else if (x[q] >= s_.upper[q])
          x[q] -= L;
      }
      p_.x[3 * i + q] = x[q];
      p_.v[3 * i + q] = v[q];
      p_.w[3 * i + q] = w[q];
    }
  }
}

// Outlets: particles whose centre left the box are no longer this rank's
// (nor anyone's); the same compaction as for ghosts drops them, order kept.
void DemSolver::drop_outlets() {
  bool outlets = false;
  for (int f = 0; f < 6; ++f) outlets = outlets || s_.faces[f] == dem::Face::outlet;
  std::unordered_map<std::int64_t, char> gone;  // owned or ghosts: gone from the run
  for (std::size_t i = 0; i < p_.size() && outlets; ++i)
    for (int q = 0; q < 3; ++q)
      if ((p_.x[3 * i + q] < s_.lower[q] && s_.faces[2 * q] == dem::Face::outlet) ||
          (p_.x[3 * i + q] > s_.upper[q] && s_.faces[2 * q + 1] == dem::Face::outlet)) {
        owned_[i] = 0;
        gone[p_.id[i]] = 1;
      }
  if (gone.empty()) return;
  // Their histories, with any partner and with walls, on any rank count (a
  // checkpoint written before the next contact list kept them; dem-reference
  // erases them at once), once the list's states are back in contacts_.
  invalidate_list();
  std::erase_if(contacts_, [&](const auto& c) {
    return gone.count(static_cast<std::int64_t>(c.first >> 32)) ||
           gone.count(static_cast<std::int64_t>(c.first & 0xffffffffu));
  });
  std::erase_if(walls_, [&](const auto& c) { return gone.count(static_cast<std::int64_t>(c.first >> 32)); });
  drop_ghosts();
}

void DemSolver::step(double h) {
  if (size_ > 1) add_ghosts();
  const std::size_t n = p_.size();
  std::fill(p_.force.begin(), p_.force.end(), 0.0);
  std::fill(torque_.begin(), torque_.end(), 0.0);
  crushed_.clear();
  if (size_ > 1 || !list_valid_ || list_stale()) build_list();
  for (std::size_t i = 0; i < n; ++i)
    for (long k = list_start_[i]; k < list_start_[i + 1]; ++k)
      pair_contact(i, static_cast<std::size_t>(list_items_[k]), k, h);
  face_contacts(h);
  mesh_contacts(h);
  // Histories of faces and triangles no longer touched.
  for (auto it = walls_.begin(); it != walls_.end();)
    it = it->second.seen != steps_ ? walls_.erase(it) : std::next(it);
  crush_grains();
  integrate_owned(h);
  if (size_ > 1) drop_ghosts();
  drop_outlets();
  if (size_ > 1) migrate();
  time_ += h;
  ++steps_;
}

// Crushing (seed 000 §2.2.2) makes grains lighter, and their critical step
// shorter than the one the run started with: each step is then split so that
// no part exceeds the automatic step of the lightest grain now (global, so
// that every rank splits alike).
long DemSolver::crushed_substeps(double h) const {
  if (s_.crush <= 0.0) return 1;
  double lightest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p_.mass.size(); ++i) lightest = std::min(lightest, p_.mass[i]);
  if (size_ > 1) MPI_Allreduce(MPI_IN_PLACE, &lightest, 1, MPI_DOUBLE, MPI_MIN, comm_);
  if (!std::isfinite(lightest)) return 1;
  if (!s_.auto_step) {
    dem::check_fixed_step(h, lightest, s_.law);
    return 1;
  }
  return dem::split_for(h, dem::automatic_step(lightest, s_.law, s_.t_frac));
}

void DemSolver::advance(double dt, long substeps) {
  const double h = dt / substeps;
  for (long k = 0; k < substeps; ++k) {
    const long n = crushed_substeps(h);
    for (long m = 0; m < n; ++m) step(h / n);
  }
}

void DemSolver::save(const std::string& dir) {
  if (list_valid_) sync_contacts();
  std::vector<dem::SavedContact> list;
  for (const auto& [k, c] : contacts_)
    list.push_back(dem::SavedContact::from(static_cast<std::int64_t>(k >> 32),
                                           static_cast<std::int64_t>(k & 0xffffffffu), c));
  for (const auto& [k, c] : walls_)
    list.push_back(dem::SavedContact::from(static_cast<std::int64_t>(k >> 32),
                                           -1 - static_cast<std::int64_t>(k & 0xffffffffu), c));
  // Canonical order, so that a checkpoint does not depend on hashing.
  std::sort(list.begin(), list.end(), [](const auto& x, const auto& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
  dem::save_state(comm_, dir, time_, steps_, p_, list, {collisions_, wall_collisions_, broken_});
}

void DemSolver::load(const std::string& dir, long steps, double time) {
  list_valid_ = false;
  std::vector<dem::SavedContact> list;
  dem::EventCounts counts;
  dem::load_state(dir, params_, p_, list, &counts);
  if (rank_ != 0) counts = {};  // stats() sums the ranks' counts
  collisions_ = counts.collisions;
  wall_collisions_ = counts.wall_collisions;
  broken_ = counts.broken_bonds;
  contacts_.clear();
  walls_.clear();
  for (const auto& c : list) {
    if (!c.wall())
      contacts_[key(c.a, c.b)] = c.state();
    else
      walls_[key(c.a, c.wall_face())] = c.state();
  }
  const std::size_t n = p_.size();
  torque_.assign(3 * n, 0.0);
  fh_.assign(3 * n, 0.0);
  th_.assign(3 * n, 0.0);
  // The checkpoint holds every rank's particles: keep this rank's.
  owned_.assign(n, 1);
  if (size_ > 1) {
    for (std::size_t i = 0; i < n; ++i) owned_[i] = domain_.owner_of(&p_.x[3 * i]) == rank_;
    drop_ghosts();
  }
  store_.sort_by_id();
  // The steps and the clock as the checkpoint kept them: crushing grains
  // take extra sub-steps, and the clock is the sum of the steps taken (the
  // windows' count alone would differ; the times of events and snapshots
  // then by round-off). A checkpoint without them: the driver's.
  const long saved = coflow::output::read_step(dir + "/particles.h5");
  steps_ = saved >= 0 ? saved : steps;
  time_ = saved >= 0 ? coflow::output::read_time(dir + "/particles.h5") : time;
}

void DemSolver::set_hydrodynamic(std::span<const double> force, std::span<const double> torque) {
  std::copy(force.begin(), force.end(), fh_.begin());
  std::copy(torque.begin(), torque.end(), th_.begin());
}

ParticleStats DemSolver::stats() {
  ParticleStats st = dem::sum_particles(comm_, p_);
  long events[3] = {collisions_, wall_collisions_, broken_}, gev[3];
  MPI_Allreduce(events, gev, 3, MPI_LONG, MPI_SUM, comm_);
  collisions_ = wall_collisions_ = 0;  // broken_bonds is cumulative
  st.collisions = gev[0];
  st.wall_collisions = gev[1];
  st.broken_bonds = gev[2];
  return st;
}

}  // namespace coflow::particles
