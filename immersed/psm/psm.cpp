#include "immersed/psm/psm.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>

#include <fmt/format.h>

#include "coflow/exchange.hpp"
#include "coflow/finite.hpp"
#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/protocol.hpp"
#include "coflow/session.hpp"
#include "coflow/trace.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::immersed {

using coupler::Box;
using coupler::Index3;
using V = std::array<double, 3>;

void PsmParams::visit(config::Visitor& v) {
  v("refinement", refinement,
    "octree levels for the cells a sphere surface cuts (3: 8^3 sub-cells, raw sphere volume within 3e-4 at "
    "radius 4 cells; 4: within 7e-5); the cut cells are then scaled so that the total is the sphere's volume",
    config::in_range(0, 8));
  v("buoyancy", buoyancy,
    "add the buoyancy -rho_f V g to each particle (the fluid carries no hydrostatic pressure gradient)");
}

double cube_fraction(const V& lo, double h, const V& c, double r, int levels) {
  // Nearest and farthest points of the cube from the centre.
  double near2 = 0.0, far2 = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double a = lo[d] - c[d], b = lo[d] + h - c[d];
    const double n = a > 0 ? a : (b < 0 ? b : 0.0);
    const double f = std::max(std::abs(a), std::abs(b));
    near2 += n * n;
    far2 += f * f;
  }
  const double r2 = r * r;
  if (near2 >= r2) return 0.0;
  if (far2 <= r2) return 1.0;
  if (levels == 0) {
    double m2 = 0.0;
    for (int d = 0; d < 3; ++d) m2 += (lo[d] + 0.5 * h - c[d]) * (lo[d] + 0.5 * h - c[d]);
    return m2 < r2 ? 1.0 : 0.0;
  }
  const double hh = 0.5 * h;
  double sum = 0.0;
  for (int k = 0; k < 8; ++k) {
    const V sub{lo[0] + (k & 1) * hh, lo[1] + ((k >> 1) & 1) * hh, lo[2] + ((k >> 2) & 1) * hh};
    sum += cube_fraction(sub, hh, c, r, levels - 1);
  }
  return 0.125 * sum;
}

namespace {

struct Share {
  std::size_t record;  // index into the received records
  double fraction;     // of the cell, by this particle
  V lever;             // cell centre - particle centre (minimum image)
};

struct Cell {
  long local = 0;      // index in the owned block
  Index3 global{};     // wrapped global cell
  double fraction = 0.0;
  V weighted_velocity{0, 0, 0};  // sum of fraction x solid velocity
  std::vector<Share> shares;
};

}  // namespace

void PsmMethod::run(coupler::Session& s) {
  const auto& cfg = s.config();
  const auto& dom = cfg.domain;
  const double h = dom.spacing()[0];
  const coupler::Decomposition mine = s.decomposition();
  const Box owned = mine.block(s.rank());
  const long nx = owned.extent(0), ny = owned.extent(1), nz = owned.extent(2);

  if (!s.has_partner("fluid") || !s.has_partner("particles"))
    throw std::runtime_error("immersed.method psm couples a fluid and particles: both sections must be present");
  particles::ParticleParams pp;
  {
    config::Reader r(cfg.resolved["particles"], cfg.file, "particles");
    pp.visit(r, cfg);
    r.check();
  }
  const double rho_f = cfg.resolved["fluid"]["density"].as<double>();
  const int ghost = particles::coupling_ghost_cells(pp, cfg);

  s.negotiate_window(0.0);
  coupler::PointExchange points(s.partner("particles"), coupler::PointExchange::Role::destination, mine, dom.lower,
                                dom.spacing(), sizeof(protocol::ParticleRecord), sizeof(protocol::ParticleLoad),
                                protocol::kTagParticles, ghost);
  const auto fluid_dec = s.decomposition_of("fluid", s.partner_ranks("fluid"));
  coupler::FieldExchange to_fluid(s.partner("fluid"), coupler::FieldExchange::Role::sender, mine, s.rank(), fluid_dec,
                                  coupler::FieldSpec{"solid", 4, coupler::Transfer::consistent, 0},
                                  protocol::kTagSolid);
  coupler::FieldExchange from_fluid(s.partner("fluid"), coupler::FieldExchange::Role::receiver, mine, s.rank(),
                                    fluid_dec, coupler::FieldSpec{"solid_force", 3, coupler::Transfer::consistent, 0},
                                    protocol::kTagSolidForce);
  log::info("psm: {} octree levels, ghost layer {} cells, buoyancy {}", p_.refinement, ghost,
            p_.buoyancy ? "on" : "off");

  output::Series series;
  if (s.rank() == 0)
    series = output::Series(s.output_dir() + "/series/immersed.csv",
                            {"time", "force_x", "force_y", "force_z", "torque_x", "torque_y", "torque_z",
                             "solid_volume"},
                            s.restart_window() > 0);

  std::vector<std::byte> records, results;
  std::vector<std::uint8_t> owned_flags;
  std::vector<protocol::ParticleRecord> rec;
  std::vector<long> slot_of(static_cast<std::size_t>(nx * ny * nz), -1);
  std::vector<Cell> cells;
  std::vector<Index3> send_cells;
  std::vector<double> send_values, got_values;
  std::vector<long> got_cells;
  std::vector<protocol::ParticleLoad> loads;
  std::vector<std::pair<Index3, double>> touched;

  for (long w = s.restart_window() + 1; w <= s.windows(); ++w) {
    // 1. Particle states.
    points.receive(records, owned_flags);
    const std::size_t n = owned_flags.size();
    rec.resize(n);
    if (n > 0) std::memcpy(rec.data(), records.data(), n * sizeof(protocol::ParticleRecord));
    // 2. Coverage of the owned cells.
    for (const Cell& c : cells) slot_of[c.local] = -1;
    cells.clear();
    double solid_volume = 0.0;
    for (std::size_t p = 0; p < n; ++p) {
      const auto& r = rec[p];
      long lo[3], hi[3];
      for (int d = 0; d < 3; ++d) {
        lo[d] = static_cast<long>(std::floor((r.x[d] - r.radius - dom.lower[d]) / h));
        hi[d] = static_cast<long>(std::floor((r.x[d] + r.radius - dom.lower[d]) / h));
      }
      // Fractions of every cell the sphere touches (owned or not, inside the
      // domain or not), so that every rank holding a copy scales the same way:
      // the cut cells are renormalised so that the sphere's cells add up to its
      // volume exactly; wholly covered cells stay 1.
      touched.clear();
      double full = 0.0, cut = 0.0;
      for (long k = lo[2]; k <= hi[2]; ++k)
        for (long j = lo[1]; j <= hi[1]; ++j)
          for (long i = lo[0]; i <= hi[0]; ++i) {
            const V corner{dom.lower[0] + i * h, dom.lower[1] + j * h, dom.lower[2] + k * h};
            const double f = cube_fraction(corner, h, {r.x[0], r.x[1], r.x[2]}, r.radius, p_.refinement);
            if (f <= 0.0) continue;
            (f >= 1.0 ? full : cut) += f;
            touched.push_back({{i, j, k}, f});
          }
      const double cells_volume = 4.0 / 3.0 * std::numbers::pi * std::pow(r.radius / h, 3);
      const double scale = cut > 0.0 ? (cells_volume - full) / cut : 1.0;
      for (const auto& [cell, raw] : touched) {
        // The unwrapped cell (for the geometry), then its wrapped index.
        Index3 g = cell;
        bool inside = true;
        for (int d = 0; d < 3; ++d) {
          const long cells_d = dom.cells[d];
          if (dom.periodic[d])
            g[d] = ((g[d] % cells_d) + cells_d) % cells_d;
          else if (g[d] < 0 || g[d] >= cells_d)
            inside = false;
        }
        if (!inside || !owned.contains(g)) continue;
        const double f = raw >= 1.0 ? 1.0 : std::min(1.0, raw * scale);
        const V centre{dom.lower[0] + (cell[0] + 0.5) * h, dom.lower[1] + (cell[1] + 0.5) * h,
                       dom.lower[2] + (cell[2] + 0.5) * h};
        const long local = ((g[2] - owned.lo[2]) * ny + (g[1] - owned.lo[1])) * nx + (g[0] - owned.lo[0]);
        if (slot_of[local] < 0) {
          slot_of[local] = static_cast<long>(cells.size());
          cells.push_back(Cell{local, g, 0.0, {0, 0, 0}, {}});
        }
        Cell& c = cells[slot_of[local]];
        const V lever{centre[0] - r.x[0], centre[1] - r.x[1], centre[2] - r.x[2]};
        // Solid velocity at the cell centre: v + omega x (x - x_p).
        const V us{r.v[0] + r.w[1] * lever[2] - r.w[2] * lever[1], r.v[1] + r.w[2] * lever[0] - r.w[0] * lever[2],
                   r.v[2] + r.w[0] * lever[1] - r.w[1] * lever[0]};
        c.fraction += f;
        for (int d = 0; d < 3; ++d) c.weighted_velocity[d] += f * us[d];
        c.shares.push_back({p, f, lever});
        solid_volume += f * h * h * h;
      }
    }
    // 3. The covered cells to the fluid: fraction (clamped at 1) and velocity.
    send_cells.clear();
    send_values.clear();
    for (const Cell& c : cells) {
      send_cells.push_back(c.global);
      send_values.push_back(std::min(1.0, c.fraction));
      for (int d = 0; d < 3; ++d) send_values.push_back(c.weighted_velocity[d] / c.fraction);
    }
    to_fluid.flush();
    to_fluid.send_sparse(send_cells, send_values);
    // 4. The force on the solid in each of those cells, after the fluid step.
    got_cells.clear();
    got_values.clear();
    from_fluid.receive_sparse(got_cells, got_values);
    // 5. Shares to the particles.
    loads.assign(n, protocol::ParticleLoad{});
    for (std::size_t m = 0; m < got_cells.size(); ++m) {
      const long slot = slot_of[got_cells[m]];
      if (slot < 0) throw std::runtime_error("psm: the fluid returned a force for a cell that holds no solid");
      const Cell& c = cells[slot];
      for (const Share& sh : c.shares) {
        const double part = sh.fraction / c.fraction;
        const V f{part * got_values[3 * m], part * got_values[3 * m + 1], part * got_values[3 * m + 2]};
        auto& l = loads[sh.record];
        for (int d = 0; d < 3; ++d) l.force[d] += f[d];
        l.torque[0] += sh.lever[1] * f[2] - sh.lever[2] * f[1];
        l.torque[1] += sh.lever[2] * f[0] - sh.lever[0] * f[2];
        l.torque[2] += sh.lever[0] * f[1] - sh.lever[1] * f[0];
      }
    }
    double total[7] = {0, 0, 0, 0, 0, 0, solid_volume};
    for (std::size_t p = 0; p < n; ++p) {
      if (p_.buoyancy && owned_flags[p]) {  // once per particle: by the rank that owns its centre
        const double volume = 4.0 / 3.0 * std::numbers::pi * std::pow(rec[p].radius, 3);
        for (int d = 0; d < 3; ++d) loads[p].force[d] -= rho_f * volume * cfg.gravity[d];
      }
      for (int d = 0; d < 3; ++d) {
        total[d] += loads[p].force[d];
        total[3 + d] += loads[p].torque[d];
      }
    }
    coupler::check_finite(s.comm(),
                          {"immersed (psm)", "particle record",
                           "the fluid's force on the solid cells is not finite: see the fluid's log"},
                          w, w * s.window(),
                          {{"hydrodynamic load (force, torque)",
                            std::span<const double>(reinterpret_cast<const double*>(loads.data()), 6 * loads.size())}},
                          6);
    results.resize(n * sizeof(protocol::ParticleLoad));
    if (n > 0) std::memcpy(results.data(), loads.data(), results.size());
    points.send_results(results);

    if (s.series_due(w)) {
      double sum[7];
      MPI_Reduce(total, sum, 7, MPI_DOUBLE, MPI_SUM, 0, s.comm());
      const double row[] = {w * s.window(), sum[0], sum[1], sum[2], sum[3], sum[4], sum[5], sum[6]};
      if (s.rank() == 0) series.row(row);
    }
    coupler::trace().steps = w;
    s.checkpoint(w, [](const std::string&) {});  // no state of its own: rebuilt every window
    s.window_done(w);
  }
  to_fluid.flush();
}

}  // namespace coflow::immersed
