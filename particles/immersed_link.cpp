#include "particles/immersed_link.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "coflow/gather.hpp"
#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/protocol.hpp"
#include "coflow/run_config.hpp"

namespace coflow::particles {

ImmersedLink::ImmersedLink(coupler::Session& s, ParticleSolver& solver, const ParticleParams& params)
    : s_(s), solver_(solver) {
  for (const auto& sp : params.species) contact_angle_.push_back(sp.second.contact_angle);
  const auto& cfg = s.config();
  point_ = config::point_coupling(cfg);
  lagged_ = !point_ && cfg.coupling.scheme == config::Scheme::parallel_explicit;
  const auto dest = s.decomposition_of("immersed", s.partner_ranks("immersed"));
  const auto h = cfg.domain.spacing();
  for (auto& x : to_immersed_)
    x = std::make_unique<coupler::PointExchange>(
        s.partner("immersed"), coupler::PointExchange::Role::origin, dest, cfg.domain.lower, h,
        sizeof(protocol::ParticleRecord), point_ ? sizeof(protocol::FluidAtParticle) : sizeof(protocol::ParticleLoad),
        protocol::kTagParticles, point_ ? 0 : coupling_ghost_cells(params, cfg));
  if (point_)
    impulse_out_ = std::make_unique<coupler::PointExchange>(
        s.partner("immersed"), coupler::PointExchange::Role::origin, dest, cfg.domain.lower, h,
        sizeof(protocol::ParticleImpulse), sizeof(double), protocol::kTagImpulse, protocol::kImpulseGhost);
}

void ImmersedLink::before_step(long w) {
  if (lagged_) {
    if (!ahead_) send_states(static_cast<int>(w % 2));
    return;
  }
  send_states(0);
  if (point_) receive_fluid();
  else apply_loads(receive_loads(0));
}

void ImmersedLink::after_step(long w) {
  if (point_) send_impulses();
  if (lagged_) {
    ahead_ = w < s_.windows();
    if (ahead_) send_states(static_cast<int>((w + 1) % 2));
    pending_ = receive_loads(static_cast<int>(w % 2));
    apply_loads(pending_);
  }
}

// The particles' states; with the point method, then the solver's probe
// points (ids -1, -2, ...; no radius or mass), where it gets the fluid too.
void ImmersedLink::send_states(int k) {
  const ParticleArrays& p = solver_.particles();
  const std::size_t n = p.size();
  const std::vector<std::array<double, 3>> probes =
      point_ ? solver_.probe_points() : std::vector<std::array<double, 3>>{};
  records_.resize((n + probes.size()) * sizeof(protocol::ParticleRecord));
  positions_.resize(n + probes.size());
  sent_ids_[k].resize(n + probes.size());
  for (std::size_t i = 0; i < n; ++i) {
    protocol::ParticleRecord rec{};
    rec.id = p.id[i];
    for (int d = 0; d < 3; ++d) {
      rec.x[d] = p.x[3 * i + d];
      rec.v[d] = p.v[3 * i + d];
      rec.w[d] = p.w[3 * i + d];
      positions_[i][d] = rec.x[d];
    }
    rec.radius = p.radius[i];
    rec.mass = p.mass[i];
    rec.contact_angle = contact_angle_.at(static_cast<std::size_t>(p.species[i]));
    sent_ids_[k][i] = p.id[i];
    std::memcpy(records_.data() + i * sizeof rec, &rec, sizeof rec);
  }
  for (std::size_t q = 0; q < probes.size(); ++q) {
    protocol::ParticleRecord rec{};
    rec.id = -1 - static_cast<std::int64_t>(q);
    for (int d = 0; d < 3; ++d) rec.x[d] = probes[q][d];
    positions_[n + q] = probes[q];
    sent_ids_[k][n + q] = rec.id;
    std::memcpy(records_.data() + (n + q) * sizeof rec, &rec, sizeof rec);
  }
  to_immersed_[k]->send(records_, positions_);
}

// Loads as (id, force, torque) rows of 7 doubles.
std::vector<double> ImmersedLink::receive_loads(int k) {
  const std::size_t n = sent_ids_[k].size();
  loads_.assign(n * sizeof(protocol::ParticleLoad), std::byte{0});
  to_immersed_[k]->receive_results(loads_, protocol::add_load);
  std::vector<double> rows(7 * n);
  for (std::size_t i = 0; i < n; ++i) {
    protocol::ParticleLoad l;
    std::memcpy(&l, loads_.data() + i * sizeof l, sizeof l);
    rows[7 * i] = static_cast<double>(sent_ids_[k][i]);
    for (int d = 0; d < 3; ++d) {
      rows[7 * i + 1 + d] = l.force[d];
      rows[7 * i + 4 + d] = l.torque[d];
    }
  }
  return rows;
}

// Hand the rows to the particles that hold these ids now; rows whose particle
// is on another rank travel to all ranks (few: those that crossed a border in
// the window); a particle that left the domain drops its row.
void ImmersedLink::apply_loads(const std::vector<double>& rows) {
  const ParticleArrays& p = solver_.particles();
  const std::size_t n = p.size();
  std::unordered_map<std::int64_t, std::size_t> slot;
  slot.reserve(n);
  for (std::size_t i = 0; i < n; ++i) slot.emplace(p.id[i], i);
  hforce_.assign(3 * n, 0.0);
  htorque_.assign(3 * n, 0.0);
  std::vector<double> away;
  auto put = [&](const double* row) {
    const auto it = slot.find(static_cast<std::int64_t>(row[0]));
    if (it == slot.end()) return false;
    for (int d = 0; d < 3; ++d) {
      hforce_[3 * it->second + d] = row[1 + d];
      htorque_[3 * it->second + d] = row[4 + d];
    }
    return true;
  };
  for (std::size_t k = 0; k < rows.size(); k += 7)
    if (!put(&rows[k])) away.insert(away.end(), &rows[k], &rows[k] + 7);
  if (s_.size() > 1) {
    const std::vector<double> all = coupler::allgather<double>(s_.comm(), away, MPI_DOUBLE);
    for (std::size_t k = 0; k < all.size(); k += 7) put(&all[k]);
  }
  solver_.set_hydrodynamic(hforce_, htorque_);
}

void ImmersedLink::save(const std::string& dir) {
  if (!lagged_) return;
  const std::vector<double> all = coupler::gather_to_root<double>(s_.comm(), pending_, MPI_DOUBLE);
  if (s_.rank() != 0) return;
  std::string f = "id,fx,fy,fz,tx,ty,tz\n";
  for (std::size_t k = 0; k < all.size(); k += 7)
    f += fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", std::int64_t(all[k]), all[k + 1],
                     all[k + 2], all[k + 3], all[k + 4], all[k + 5], all[k + 6]);
  output::atomic_write(dir + "/hydrodynamic.csv", f);  // judged after the close (a full disk shows there)
}

void ImmersedLink::load(const std::string& dir) {
  if (!lagged_) return;
  std::ifstream f(dir + "/hydrodynamic.csv");
  if (!f) throw std::runtime_error(dir + "/hydrodynamic.csv: missing (the checkpoint of a parallel-explicit run)");
  std::string line;
  std::getline(f, line);
  std::vector<double> rows;
  while (std::getline(f, line)) {
    std::istringstream in(line);
    std::string cell;
    while (std::getline(in, cell, ',')) rows.push_back(config::to_number(cell));
  }
  if (rows.size() % 7 != 0) throw std::runtime_error(dir + "/hydrodynamic.csv: malformed");
  for (std::size_t k = 0; k < rows.size(); ++k)  // every rank reads all rows: all throw alike
    if (!std::isfinite(rows[k]))
      throw std::runtime_error(
          fmt::format("{}/hydrodynamic.csv: the load on particle {} is not finite: the "
                      "checkpoint is damaged; restart from another one",
                      dir, rows[k - k % 7]));
  // Every rank read all rows: keep those of its own particles.
  const ParticleArrays& p = solver_.particles();
  std::unordered_map<std::int64_t, std::size_t> slot;
  for (std::size_t i = 0; i < p.size(); ++i) slot.emplace(p.id[i], i);
  std::vector<double> mine;
  for (std::size_t k = 0; k < rows.size(); k += 7)
    if (slot.count(static_cast<std::int64_t>(rows[k]))) mine.insert(mine.end(), &rows[k], &rows[k] + 7);
  // A row for every particle: one without would take no load in the first
  // window (a damaged file, or one cut short). Rows of particles gone are
  // kept: the loads are those of the window's start, and a grain may have
  // left through an outlet since.
  long counts[2] = {static_cast<long>(p.size()), static_cast<long>(mine.size() / 7)};
  MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_LONG, MPI_SUM, s_.comm());
  if (counts[1] != counts[0])
    throw std::runtime_error(
        fmt::format("{}/hydrodynamic.csv: {} rows, {} of them for the checkpoint's {} particles: "
                    "the checkpoint is damaged; restart from another one",
                    dir, rows.size() / 7, counts[1], counts[0]));
  pending_ = mine;
  apply_loads(mine);
}

void ImmersedLink::receive_fluid() {
  const std::size_t n = sent_ids_[0].size();
  fluid_bytes_.assign(n * sizeof(protocol::FluidAtParticle), std::byte{0});
  to_immersed_[0]->receive_results(fluid_bytes_);
  samples_.resize(ParticleSolver::kFluidValues * n);
  for (std::size_t i = 0; i < n; ++i) {
    protocol::FluidAtParticle f;
    std::memcpy(&f, fluid_bytes_.data() + i * sizeof f, sizeof f);
    double* row = &samples_[ParticleSolver::kFluidValues * i];
    for (int d = 0; d < 3; ++d) {
      row[d] = f.u[d];
      row[3 + d] = f.vorticity[d];
    }
    row[6] = f.k;
    row[7] = f.epsilon;
    row[8] = f.rho;
    row[9] = f.mu;
  }
  solver_.set_fluid(samples_);
}

// The window's impulses of the particles here, then of those that left
// through an outlet (at their last position inside).
void ImmersedLink::send_impulses() {
  solver_.take_impulse(impulse_);
  solver_.take_departed(departed_);
  const ParticleArrays& p = solver_.particles();
  const std::size_t n = p.size(), m = n + departed_.size();
  impulse_records_.resize(m * sizeof(protocol::ParticleImpulse));
  positions_.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    protocol::ParticleImpulse rec{};
    rec.id = i < n ? p.id[i] : departed_[i - n].id;
    for (int d = 0; d < 3; ++d) {
      rec.x[d] = i < n ? p.x[3 * i + d] : departed_[i - n].x[d];
      rec.impulse[d] = i < n ? impulse_[3 * i + d] : departed_[i - n].impulse[d];
      positions_[i][d] = rec.x[d];
    }
    std::memcpy(impulse_records_.data() + i * sizeof rec, &rec, sizeof rec);
  }
  impulse_out_->send(impulse_records_, positions_);
  check_crossing();
}

// The point method samples the fluid at a particle once a window, at its
// start position, and spreads the impulse at its end position: a particle
// that crosses more than a cell in a window sees stale fluid and gives its
// momentum off its path. Said once, from the fastest particle (collective).
void ImmersedLink::check_crossing() {
  if (warned_fast_) return;
  const ParticleArrays& p = solver_.particles();
  double vmax = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    vmax = std::max(vmax, std::hypot(p.v[3 * i], p.v[3 * i + 1], p.v[3 * i + 2]));
  MPI_Allreduce(MPI_IN_PLACE, &vmax, 1, MPI_DOUBLE, MPI_MAX, s_.comm());
  const auto& dom = s_.config().domain;
  const auto h = dom.spacing();
  double hmin = 1e300;  // over the axes with more than one cell (a 2D grid's depth is no cell to cross)
  for (int d = 0; d < 3; ++d)
    if (dom.cells[d] > 1) hmin = std::min(hmin, h[d]);
  const double cells = vmax * s_.window() / hmin;
  if (!(cells > 1.0)) return;
  warned_fast_ = true;
  if (s_.rank() == 0)
    log::warn(
        "particles cross up to {:.3g} fluid cells in one coupling window ({:.3g} m/s): the point method "
        "samples the fluid once a window at a particle's start and spreads its impulse at its end; a "
        "coupling.window of at most {:.3g} s keeps them within a cell",
        cells, vmax, hmin / vmax);
}

}  // namespace coflow::particles
