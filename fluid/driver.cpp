#include "fluid/driver.hpp"

#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/exchange.hpp"
#include "coflow/protocol.hpp"
#include "fluid/schema.hpp"

namespace coflow::fluid {

FluidParams read_params(const config::Config& cfg) {
  FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);  // the resolved file was validated: no problems, no finish()
  r.check();
  return p;
}

std::unique_ptr<FluidSolver> make_solver(const FluidSolver::Setup& setup) {
  const auto& cfg = setup.cfg;
  const auto& entry = registry().at(cfg.component("fluid").variant);
  YAML::Node sub = entry.params_section.empty() ? YAML::Node() : cfg.resolved["fluid"][entry.params_section];
  config::Reader r(sub, cfg.file, "fluid." + entry.params_section);
  std::unique_ptr<FluidSolver> solver = entry.create(setup, r);
  r.check();
  return solver;
}

namespace {

void write_series(output::Series& series, double t, const Diagnostics& d) {
  const double row[] = {t, d.mass, d.momentum[0], d.momentum[1], d.momentum[2], d.kinetic_energy,
                        d.max_velocity, d.max_mach};
  series.row(row);
}

}  // namespace

void run(coupler::Session& s) {
  const auto& cfg = s.config();
  const auto& info = cfg.component("fluid");
  if (info.variant == "external")
    throw std::runtime_error(
        "fluid.solver is 'external': run your own executable with `coflow run --exe fluid=PATH`");
  const FluidParams params = read_params(cfg);
  std::unique_ptr<FluidSolver> solver = make_solver({cfg, params, s.decomposition(), s.rank(), s.comm()});

  const double dt = solver->time_step();
  const double window = s.negotiate_window(dt);
  if (dt > 0) {
    const double ratio = window / dt;
    if (std::abs(ratio - std::round(ratio)) > 1e-6 * ratio)
      throw config::ConfigError({config::Problem{cfg.file, 0, 0, "coupling.window",
                                                 fmt::format("must be a whole number of fluid steps ({:.6g} s); got {:.6g} s",
                                                             dt, window)}});
  }

  const long per_window = dt > 0 ? std::lround(window / dt) : 1;
  const long w0 = s.restart_window();
  if (w0 > 0) solver->load(s.restart_dir(), w0 * per_window, w0 * window);

  output::Series series;
  if (s.rank() == 0)
    series = output::Series(s.output_dir() + "/series/fluid.csv",
                            {"time", "mass", "momentum_x", "momentum_y", "momentum_z", "kinetic_energy",
                             "max_velocity", "max_mach"},
                            w0 > 0);
  auto write_output = [&](long w) {
    coupler::Timer t(coupler::trace().io_s);
    const double time = solver->time();
    if (s.series_due(w)) {
      const Diagnostics d = solver->diagnostics();
      if (s.rank() == 0) write_series(series, time, d);
      s.set_final("fluid.mass", d.mass);
      s.set_final("fluid.momentum_x", d.momentum[0]);
      s.set_final("fluid.momentum_y", d.momentum[1]);
      s.set_final("fluid.momentum_z", d.momentum[2]);
      s.set_final("fluid.kinetic_energy", d.kinetic_energy);
    }
    if (s.snapshot_due(w)) {
      const auto fields = solver->fields(cfg.run.output.fields);
      const auto& c = cfg.domain.cells;
      output::write_grid(s.comm(), fmt::format("{}/{}", s.component_dir(), output::snapshot_name(w)), time, w,
                         {c[0], c[1], c[2]}, solver->owned(), solver->owned(), fields);
      std::vector<std::string> names;
      for (const auto& f : fields) names.push_back(f.name);
      s.snapshot_written(w, time, 0, names);
    }
  };

  // Coupled through partially saturated cells (immersed method psm): each window
  // the covered cells with their solid fraction and velocity arrive before the
  // step, and the force the fluid exerted on the solid in them goes back after.
  const bool psm = s.has_partner("immersed") && cfg.component("immersed").variant == "psm";
  std::unique_ptr<coupler::FieldExchange> solid_in, force_out;
  if (psm) {
    const auto other = s.decomposition_of("immersed", s.partner_ranks("immersed"));
    solid_in = std::make_unique<coupler::FieldExchange>(
        s.partner("immersed"), coupler::FieldExchange::Role::receiver, s.decomposition(), s.rank(), other,
        coupler::FieldSpec{"solid", 4, coupler::Transfer::consistent, 0}, protocol::kTagSolid);
    force_out = std::make_unique<coupler::FieldExchange>(
        s.partner("immersed"), coupler::FieldExchange::Role::sender, s.decomposition(), s.rank(), other,
        coupler::FieldSpec{"solid_force", 3, coupler::Transfer::consistent, 0}, protocol::kTagSolidForce);
  }
  // Point particles (immersed method point): the fluid's velocity, k and
  // epsilon go out at each window's start (ghost layer 2 for the immersed side's
  // interpolation and vorticity), and the particles' momentum source of the
  // window comes back before the step.
  const bool point = s.has_partner("immersed") && cfg.component("immersed").variant == "point";
  std::unique_ptr<coupler::FieldExchange> flow_out, source_in;
  std::vector<double> flow_local, source_local, source_owned;
  if (point) {
    const auto other = s.decomposition_of("immersed", s.partner_ranks("immersed"));
    flow_out = std::make_unique<coupler::FieldExchange>(
        s.partner("immersed"), coupler::FieldExchange::Role::sender, s.decomposition(), s.rank(), other,
        coupler::FieldSpec{"flow", 5, coupler::Transfer::consistent, 2}, protocol::kTagFlow);
    source_in = std::make_unique<coupler::FieldExchange>(
        s.partner("immersed"), coupler::FieldExchange::Role::receiver, s.decomposition(), s.rank(), other,
        coupler::FieldSpec{"source", 3, coupler::Transfer::conservative, 1}, protocol::kTagSource);
    flow_local.assign(flow_out->local_size(), 0.0);
    source_local.assign(source_in->local_size(), 0.0);
  }
  auto send_flow = [&] {
    flow_out->flush();
    const auto fields = solver->fields({"velocity", "k", "epsilon"});
    const coupler::Box& o = solver->owned();
    const long nx = o.extent(0), ny = o.extent(1);
    for (const auto& f : fields) {
      const int first = f.name == "velocity" ? 0 : f.name == "k" ? 3 : 4;
      for (long k = o.lo[2]; k < o.hi[2]; ++k)
        for (long j = o.lo[1]; j < o.hi[1]; ++j)
          for (long i = o.lo[0]; i < o.hi[0]; ++i) {
            const long c = ((k - o.lo[2]) * ny + (j - o.lo[1])) * nx + (i - o.lo[0]);
            const long l = flow_out->local_index({i, j, k});
            for (int d = 0; d < f.components; ++d) flow_local[5 * l + first + d] = f.data[f.components * c + d];
          }
    }
    flow_out->send(flow_local);
  };
  auto receive_source = [&] {
    source_in->receive(source_local);
    const coupler::Box& o = solver->owned();
    source_owned.resize(3 * o.volume());
    std::size_t c = 0;
    for (long k = o.lo[2]; k < o.hi[2]; ++k)
      for (long j = o.lo[1]; j < o.hi[1]; ++j)
        for (long i = o.lo[0]; i < o.hi[0]; ++i, ++c) {
          const long l = source_in->local_index({i, j, k});
          for (int d = 0; d < 3; ++d) source_owned[3 * c + d] = source_local[3 * l + d];
        }
    solver->set_source(source_owned);
  };
  std::vector<long> solid_cells;
  std::vector<double> solid_values, fraction, velocity, force;
  std::vector<coupler::Index3> force_cells;
  const coupler::Box owned = solver->owned();

  // The initial snapshot is written once the first window's solids are in, so
  // that it shows them.
  if (w0 == 0 && !psm) write_output(0);
  for (long w = w0 + 1; w <= s.windows(); ++w) {
    if (psm) {
      solid_cells.clear();
      solid_values.clear();
      solid_in->receive_sparse(solid_cells, solid_values);
      const std::size_t n = solid_cells.size();
      fraction.resize(n);
      velocity.resize(3 * n);
      for (std::size_t c = 0; c < n; ++c) {
        fraction[c] = solid_values[4 * c];
        for (int d = 0; d < 3; ++d) velocity[3 * c + d] = solid_values[4 * c + 1 + d];
      }
      solver->set_solid(solid_cells, fraction, velocity);
      if (w == 1) write_output(0);
    }
    if (point) {
      send_flow();
      receive_source();
    }
    solver->advance(window);
    if (psm) {
      solver->take_solid_force(force);
      force_out->flush();  // the previous window's message may still read force_cells
      force_cells.resize(solid_cells.size());
      const long nx = owned.extent(0), ny = owned.extent(1);
      for (std::size_t c = 0; c < solid_cells.size(); ++c) {
        const long l = solid_cells[c];
        force_cells[c] = {owned.lo[0] + l % nx, owned.lo[1] + (l / nx) % ny, owned.lo[2] + l / (nx * ny)};
      }
      force_out->send_sparse(force_cells, force);
    }
    coupler::trace().steps = solver->steps();
    write_output(w);
    s.checkpoint(w, [&](const std::string& dir) { solver->save(dir); });
    s.window_done(w);
  }
  if (force_out) force_out->flush();
  if (flow_out) flow_out->flush();
}

}  // namespace coflow::fluid
