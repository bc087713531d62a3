#include "fluid/driver.hpp"

#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "fluid/schema.hpp"

namespace coflow::fluid {

namespace {

FluidParams read_params(const config::Config& cfg) {
  FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);  // the resolved file was validated: no problems, no finish()
  r.check();
  return p;
}

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
  const auto& entry = registry().at(info.variant);
  FluidSolver::Setup setup{cfg, params, s.decomposition(), s.rank(), s.comm()};
  YAML::Node sub = entry.params_section.empty() ? YAML::Node() : cfg.resolved["fluid"][entry.params_section];
  config::Reader r(sub, cfg.file, "fluid." + entry.params_section);
  std::unique_ptr<FluidSolver> solver = entry.create(setup, r);
  r.check();

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

  if (w0 == 0) write_output(0);
  for (long w = w0 + 1; w <= s.windows(); ++w) {
    solver->advance(window);
    coupler::trace().steps = solver->steps();
    write_output(w);
    s.checkpoint(w, [&](const std::string& dir) { solver->save(dir); });
    s.window_done(w);
  }
}

}  // namespace coflow::fluid
