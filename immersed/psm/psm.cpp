#include "immersed/psm/psm.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "coflow/exchange.hpp"
#include "coflow/finite.hpp"
#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/protocol.hpp"
#include "coflow/run_config.hpp"
#include "coflow/session.hpp"
#include "coflow/trace.hpp"
#include "coflow/window_loop.hpp"
#include "immersed/order_by_id.hpp"
#include "immersed/psm/cell_halo.hpp"
#include "immersed/psm/record_check.hpp"
#include "immersed/series.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::immersed {

using coupler::Box;
using coupler::Index3;
using V = std::array<double, 3>;

namespace {

// A share of an owned particle (the rank owning its centre sums all of them):
// in an owned cell (a slot) or in another rank's (a ghost cell, whose force
// comes through the cell halo).
struct Share {
  static constexpr std::size_t ghost = std::size_t{1} << 63;  // slot flag: an index into ghost_cells
  std::size_t record;  // index into the received records
  std::size_t slot;    // index into the covered cells, or ghost | index into the ghost cells
  double fraction;     // of the cell, by this particle
  V lever;             // cell centre - particle centre (minimum image)
};

struct Cell {
  long local = 0;  // index in the owned block (x fastest)
  double fraction = 0.0;
  V weighted_velocity{0, 0, 0};  // sum of fraction x solid velocity
  double weighted_wetting = 0.0;  // sum of fraction x cos(contact angle)
};

// What one window's particle states cover: the records as they came (ghost
// copies too), the covered owned cells and each particle's share of them.
struct Coverage {
  std::vector<std::byte> records;
  std::vector<std::uint8_t> owned_flags;
  std::vector<protocol::ParticleRecord> rec;
  std::vector<std::int32_t> slot_of;  // owned cell -> index in cells, or -1 (4 bytes: half the cache misses)
  std::vector<Cell> cells;
  std::vector<Index3> global;  // each cell's global index, for the fluid
  std::vector<Index3> ghost_cells;  // the owned particles' cells owned by other ranks (global index, wrapped)
  std::vector<std::size_t> order;   // the records by particle id: the order they are covered in
  std::vector<Share> shares;        // owned particle by particle (by id), cell by cell
  double solid_volume = 0.0;
};

}  // namespace

namespace {

coupler::PointExchange particle_exchange(coupler::Session& s, int ghost) {
  const auto& dom = s.config().domain;
  return coupler::PointExchange(s.partner("particles"), coupler::PointExchange::Role::destination,
                                s.decomposition(), dom.lower, dom.spacing(), sizeof(protocol::ParticleRecord),
                                sizeof(protocol::ParticleLoad), protocol::kTagParticles, ghost);
}

// One window of psm: 1. the particle states arrive; 2. the coverage of the
// owned cells; 3. the covered cells go to the fluid, fraction (clamped at 1),
// velocity and, for a two-phase fluid, wetting (cos of the contact angle); 4. the force on the solid in each
// of them comes back after the fluid step, as the replies to 3; 5. each particle gets its shares, with
// buoyancy, and they go back. parallel-explicit pipelines 1-2: the particles send the next window's states as
// soon as they have stepped (on the previous window's loads), and this component covers them while the fluid
// steps the current window, so that neither the covering nor the particles sit between two fluid steps. Two
// coverages and two point exchanges alternate, window by window.
class PsmWindows final : public coupler::WindowParts {
 public:
  PsmWindows(coupler::Session& s, const PsmParams& p, int ghost, std::vector<double> kept_radii);
  void start(long) override { ahead_ = false; }
  void before_step(long w) override;  // 1, 2
  void step(long w) override;         // 3, (1, 2 of w + 1), 4
  void after_step(long w) override;  // 5
  void output(long w) override;
  void save(const std::string&) override {}  // no state of its own: rebuilt every window
  void finish() override {
    to_fluid_.flush();
    if (p_.centre_lattice > 0)
      log::info("psm: {} fraction stencils kept, {} of them computed by the octree (the others by symmetry)",
                fractions_.stencils_computed(), fractions_.octree_stencils());
    log::info(
        "psm: {} of {} covers kept from the window before (the sphere's rounded placement had not changed)",
        fractions_.lists_reused(), fractions_.lists_asked());
  }

 private:
  void receive_and_cover(long w);
  void cover(Coverage& c, std::size_t p);
  void add_cell(Coverage& c, std::size_t p, const Index3& cell, double f, double wetting);
  const double* force_per_fraction(const Coverage& c, const Share& sh) const;
  void share_forces(const Coverage& c);

  coupler::Session& s_;
  const config::DomainParams& dom_;
  const PsmParams& p_;
  double h_;
  Box owned_;
  double rho_f_;
  bool pipelined_;  // parallel-explicit: windows alternate between two of each
  bool ahead_ = false;  // the coverage of the coming window is already in
  coupler::PointExchange points_[2];
  Coverage coverage_[2];
  coupler::FieldExchange to_fluid_;  // the solid's cells; the fluid's force comes back as the replies
  std::vector<std::byte> results_;
  std::vector<double> send_values_,
      slot_force_;  // slot_force_: the fluid's force per covered cell, then per unit of fraction
  std::vector<protocol::ParticleLoad> loads_;
  SphereFractions fractions_;
  psm::CellHalo halo_;           // the force per unit fraction of the cells near the other immersed ranks
  double default_angle_ = 90.0;  // fluid.two_phase.contact_angle, for species without their own
  double total_[7] = {};
  ImmersedSeries series_;
};

PsmWindows::PsmWindows(coupler::Session& s, const PsmParams& p, int ghost, std::vector<double> kept_radii)
    : s_(s),
      dom_(s.config().domain),
      p_(p),
      h_(dom_.spacing()[0]),
      owned_(s.decomposition().block(s.rank())),
      rho_f_(s.config().resolved["fluid"]["density"].as<double>()),
      pipelined_(s.config().coupling.scheme == config::Scheme::parallel_explicit),
      points_{particle_exchange(s, ghost), particle_exchange(s, ghost)},
      to_fluid_(s.partner("fluid"), coupler::FieldExchange::Role::sender, s.decomposition(), s.rank(),
                s.decomposition_of("fluid", s.partner_ranks("fluid")),
                coupler::FieldSpec{"solid", protocol::solid_values(config::two_phase_fluid(s.config())),
                                   coupler::Transfer::consistent, 0},
                protocol::kTagSolid),
      fractions_(h_, dom_.lower, p.refinement, p.centre_lattice, std::move(kept_radii),
                 std::size_t{256} << 20, p.blend_steps),
      halo_(s.comm(), s.decomposition(), s.rank(), ghost),
      series_(s) {
  default_angle_ =
      config::resolved_number(s.config(), {"fluid", "two_phase", "contact_angle"}, default_angle_);
  if (owned_.volume() > std::numeric_limits<std::int32_t>::max())
    throw std::runtime_error(
        fmt::format("psm: {} cells on one immersed rank (at most 2^31 - 1); run immersed on more ranks",
                    owned_.volume()));
  for (Coverage& c : coverage_) c.slot_of.assign(static_cast<std::size_t>(owned_.volume()), -1);
  log::info("psm: {} octree levels, {}, ghost layer {} cells, buoyancy {}", p_.refinement,
            p_.centre_lattice > 0 ? fmt::format("fractions kept for centres on a lattice of h/{}", p_.centre_lattice)
                                  : std::string("fractions at the exact centres"),
            ghost, p_.buoyancy ? "on" : "off");
}

// The states of window w's particles (at its start), and the cells they cover.
void PsmWindows::receive_and_cover(long w) {
  const int k = pipelined_ ? static_cast<int>(w % 2) : 0;
  Coverage& c = coverage_[k];
  points_[k].receive(c.records, c.owned_flags);
  const std::size_t n = c.owned_flags.size();
  c.rec.resize(n);
  if (n > 0) std::memcpy(c.rec.data(), c.records.data(), n * sizeof(protocol::ParticleRecord));
  // Forget the last window's cells: one by one where they are few, else the
  // whole map at once (a sweep of 4 bytes per owned cell instead of a read of
  // every covered cell's record).
  if (c.cells.size() * sizeof(Cell) < c.slot_of.size() * sizeof(std::int32_t))
    for (const Cell& cell : c.cells) c.slot_of[cell.local] = -1;
  else
    std::fill(c.slot_of.begin(), c.slot_of.end(), -1);
  c.cells.clear();
  c.global.clear();
  c.ghost_cells.clear();
  c.shares.clear();
  c.solid_volume = 0.0;
  for (const auto& r : c.rec) psm::check_record(r, dom_);
  order_by_id(n, c.order, [&c](std::size_t p) { return c.rec[p].id; });
  for (const std::size_t p : c.order) cover(c, p);
  fractions_.forget_unasked();
}

void PsmWindows::before_step(long w) {
  if (!ahead_) receive_and_cover(w);
}

void PsmWindows::step(long w) {
  const Coverage& c = coverage_[pipelined_ ? w % 2 : 0];
  send_values_.clear();
  const bool wetted = to_fluid_.spec().components == 5;  // a two-phase fluid: the grains' wetting too
  for (const Cell& cell : c.cells) {
    send_values_.push_back(std::min(1.0, cell.fraction));
    for (int d = 0; d < 3; ++d) send_values_.push_back(cell.weighted_velocity[d] / cell.fraction);
    if (wetted) send_values_.push_back(cell.weighted_wetting / cell.fraction);
  }
  to_fluid_.send_sparse(c.global, send_values_);
  // While the fluid steps: the next window's states, sent by the particles
  // once they have stepped this window.
  ahead_ = pipelined_ && w < s_.windows();
  if (ahead_) receive_and_cover(w + 1);
  // The fluid's force in each cell sent, in the order sent: cell n is slot n.
  slot_force_.resize(3 * c.cells.size());
  to_fluid_.receive_replies(slot_force_, 3);
}

// The fractions of every cell the sphere touches (owned or not, inside the
// domain or not: a pure function of its centre and radius, so that every rank
// holding a copy has the same ones; fractions.hpp).
void PsmWindows::cover(Coverage& c, std::size_t p) {
  const auto& r = c.rec[p];
  const auto& touched = fractions_.cover_of(r.id, {r.x[0], r.x[1], r.x[2]}, r.radius);
  const double angle = r.contact_angle < 0.0 ? default_angle_ : r.contact_angle;
  const double wetting = std::cos(angle * std::numbers::pi / 180.0);
  for (const auto& [cell, f] : touched) add_cell(c, p, cell, f, wetting);
}

// Particle p covers fraction f of the (unwrapped) cell: add it when the
// wrapped cell is in the domain and owned here; the particle's share of it when
// the particle is owned here (its centre is in the owned block), whoever owns
// the cell.
void PsmWindows::add_cell(Coverage& cov, std::size_t p, const Index3& cell, double f, double wetting) {
  const auto& r = cov.rec[p];
  const double h = h_;
  Index3 g = cell;
  for (int d = 0; d < 3; ++d) {
    const long cells_d = dom_.cells[d];
    if (dom_.periodic[d]) {  // a sphere reaches past a face by less than a period: no division
      while (g[d] < 0) g[d] += cells_d;
      while (g[d] >= cells_d) g[d] -= cells_d;
    } else if (g[d] < 0 || g[d] >= cells_d) {
      return;
    }
  }
  const bool mine = cov.owned_flags[p] != 0;
  const V centre{dom_.lower[0] + (cell[0] + 0.5) * h, dom_.lower[1] + (cell[1] + 0.5) * h,
                 dom_.lower[2] + (cell[2] + 0.5) * h};
  const V lever{centre[0] - r.x[0], centre[1] - r.x[1], centre[2] - r.x[2]};
  if (!owned_.contains(g)) {
    if (mine) {
      cov.shares.push_back({p, Share::ghost | cov.ghost_cells.size(), f, lever});
      cov.ghost_cells.push_back(g);
    }
    return;
  }
  const long nx = owned_.extent(0), ny = owned_.extent(1);
  const long local = ((g[2] - owned_.lo[2]) * ny + (g[1] - owned_.lo[1])) * nx + (g[0] - owned_.lo[0]);
  if (cov.slot_of[local] < 0) {
    cov.slot_of[local] = static_cast<std::int32_t>(cov.cells.size());
    cov.cells.push_back(Cell{local, 0.0, {0, 0, 0}, 0.0});
    cov.global.push_back(g);
  }
  Cell& c = cov.cells[cov.slot_of[local]];
  // Solid velocity at the cell centre: v + omega x (x - x_p).
  const V us{r.v[0] + r.w[1] * lever[2] - r.w[2] * lever[1], r.v[1] + r.w[2] * lever[0] - r.w[0] * lever[2],
             r.v[2] + r.w[0] * lever[1] - r.w[1] * lever[0]};
  c.fraction += f;
  for (int d = 0; d < 3; ++d) c.weighted_velocity[d] += f * us[d];
  c.weighted_wetting += f * wetting;
  if (mine) cov.shares.push_back({p, static_cast<std::size_t>(cov.slot_of[local]), f, lever});
  cov.solid_volume += f * h * h * h;
}

// The fluid's force per unit of fraction in a share's cell: an owned cell's,
// or the one its owner sent through the halo.
const double* PsmWindows::force_per_fraction(const Coverage& cov, const Share& sh) const {
  if ((sh.slot & Share::ghost) == 0) return &slot_force_[3 * sh.slot];
  const Index3& g = cov.ghost_cells[sh.slot & ~Share::ghost];
  const double* got = halo_.find(g);
  if (got == nullptr)
    throw std::logic_error(
        fmt::format("psm: particle {} covers cell ({}, {}, {}), but the immersed rank owning "
                    "the cell sent no force for it (ghost layer too thin)",
                    cov.rec[sh.record].id, g[0], g[1], g[2]));
  return got;
}

// Each particle's share (by fraction) of the force in the cells it covers, and
// the torque of those shares about its centre (seed 000 eqs 2.70-2.71; eq.
// 2.71 as printed, v x (x_n - x_p) with a minus, is F x r: the torque here is
// r x F, the lever from the centre to the cell crossed with its force), summed
// by the rank owning its centre (the other ranks holding a copy return zero).
void PsmWindows::share_forces(const Coverage& cov) {
  loads_.assign(cov.rec.size(), protocol::ParticleLoad{});
  // In the order of the shares (particle by particle, cell by cell), not of
  // the cells' arrival, and all on one rank, so that the sums do not depend
  // on the fluid's or immersed's decomposition (1 rank = N, bit for bit).
  for (std::size_t slot = 0; slot < cov.cells.size(); ++slot) {
    // The force per unit of fraction: a share takes its fraction of it.
    const double per = 1.0 / cov.cells[slot].fraction;
    for (int d = 0; d < 3; ++d) slot_force_[3 * slot + d] *= per;
  }
  halo_.exchange(cov.global, slot_force_, 3);
  for (const Share& sh : cov.shares) {
    const double* got = force_per_fraction(cov, sh);
    const V f{sh.fraction * got[0], sh.fraction * got[1], sh.fraction * got[2]};
    auto& l = loads_[sh.record];
    for (int d = 0; d < 3; ++d) l.force[d] += f[d];
    l.torque[0] += sh.lever[1] * f[2] - sh.lever[2] * f[1];
    l.torque[1] += sh.lever[2] * f[0] - sh.lever[0] * f[2];
    l.torque[2] += sh.lever[0] * f[1] - sh.lever[1] * f[0];
  }
}

void PsmWindows::after_step(long w) {
  const int k = pipelined_ ? static_cast<int>(w % 2) : 0;
  const Coverage& cov = coverage_[k];
  share_forces(cov);
  const std::size_t n = cov.rec.size();
  const auto& g = s_.config().gravity;
  std::fill(total_, total_ + 6, 0.0);
  total_[6] = cov.solid_volume;
  for (std::size_t p = 0; p < n; ++p) {
    // The hydrostatic gradient the lattice Boltzmann fluid does not carry. (The
    // gradient fluid.body_force stands for reaches the solid in the fluid's
    // force: each cell's solid share of it, fluid/lbm/psm_kernel.hpp.)
    if (p_.buoyancy && cov.owned_flags[p]) {  // once per particle: by the rank that owns its centre
      const double volume = 4.0 / 3.0 * std::numbers::pi * std::pow(cov.rec[p].radius, 3);
      for (int d = 0; d < 3; ++d) loads_[p].force[d] -= rho_f_ * volume * g[d];
    }
    for (int d = 0; d < 3; ++d) {
      total_[d] += loads_[p].force[d];
      total_[3 + d] += loads_[p].torque[d];
    }
  }
  coupler::check_finite(s_.comm(),
                        {"immersed (psm)", "particle record",
                         "the fluid's force on the solid cells is not finite: see the fluid's log"},
                        w, w * s_.window(),
                        {{"hydrodynamic load (force, torque)",
                          std::span<const double>(reinterpret_cast<const double*>(loads_.data()), 6 * loads_.size())}},
                        6);
  results_.resize(n * sizeof(protocol::ParticleLoad));
  if (n > 0) std::memcpy(results_.data(), loads_.data(), results_.size());
  points_[k].send_results(results_);
  coupler::trace().steps = w;
}

void PsmWindows::output(long w) { series_.write(w, total_); }

}  // namespace

void PsmMethod::run(coupler::Session& s) {
  const auto& cfg = s.config();
  if (!s.has_partner("fluid") || !s.has_partner("particles"))
    throw std::runtime_error("immersed.method psm couples a fluid and particles: both sections must be present");
  particles::ParticleParams pp;
  {
    config::Reader r(cfg.resolved["particles"], cfg.file, "particles");
    pp.visit(r, cfg);
    r.check();
  }
  const int ghost = particles::coupling_ghost_cells(pp, cfg);
  s.negotiate_window(0.0);
  // The species of one diameter keep their stencils (fractions.hpp).
  std::vector<double> kept_radii;
  for (const auto& [name, sp] : pp.species)
    if (sp.diameter.kind == config::Distribution::Kind::fixed) kept_radii.push_back(0.5 * sp.diameter.a);
  PsmWindows windows(s, p_, ghost, std::move(kept_radii));
  coupler::run_windows(s, windows);
}

}  // namespace coflow::immersed
