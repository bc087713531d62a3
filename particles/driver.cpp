#include "particles/driver.hpp"

#include <memory>

#include <fmt/format.h>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "particles/schema.hpp"

namespace coflow::particles {

void run(coupler::Session& s) {
  const auto& cfg = s.config();
  const auto& info = cfg.component("particles");
  if (info.variant == "external")
    throw std::runtime_error(
        "particles.solver is 'external': run your own executable with `coflow run --exe particles=PATH`");
  ParticleParams params;
  {
    config::Reader r(cfg.resolved["particles"], cfg.file, "particles");
    params.visit(r, cfg);
    r.check();
  }
  const auto& entry = registry().at(info.variant);
  ParticleSolver::Setup setup{cfg, params, s.decomposition(), s.rank(), s.comm()};
  config::Reader r(YAML::Node(), cfg.file, "particles");
  std::unique_ptr<ParticleSolver> solver = entry.create(setup, r);

  // Particles sub-cycle inside the fluid's window; alone, one window per output
  // interval.
  s.negotiate_window(0.0);
  const long substeps = s.substeps(solver->time_step());
  log::info("particles: step {:.4g} s, {} sub-steps of {:.4g} s per window", solver->time_step(), substeps,
            s.window() / substeps);

  const long w0 = s.restart_window();
  if (w0 > 0) solver->load(s.restart_dir(), w0 * substeps, w0 * s.window());

  output::Series series;
  if (s.rank() == 0)
    series = output::Series(s.output_dir() + "/series/particles.csv",
                            {"time", "count", "momentum_x", "momentum_y", "momentum_z", "kinetic_energy",
                             "collisions", "wall_collisions", "broken_bonds", "rotational_energy"},
                            w0 > 0);
  auto write_output = [&](long w) {
    coupler::Timer t(coupler::trace().io_s);
    if (s.series_due(w)) {
      const ParticleStats st = solver->stats();
      const double row[] = {solver->time(), double(st.count), st.momentum[0], st.momentum[1], st.momentum[2],
                            st.kinetic_energy, double(st.collisions), double(st.wall_collisions),
                            double(st.broken_bonds), st.rotational_energy};
      if (s.rank() == 0) series.row(row);
      s.set_final("particles.count", double(st.count));
      s.set_final("particles.kinetic_energy", st.kinetic_energy);
      s.set_final("particles.broken_bonds", double(st.broken_bonds));
    }
    if (s.snapshot_due(w)) {
      const ParticleArrays& p = solver->particles();
      std::vector<double> diam(p.radius);
      const std::vector<output::PointField> fields{{"position", 3, p.x},       {"velocity", 3, p.v},
                                                   {"angular_velocity", 3, p.w}, {"radius", 1, p.radius},
                                                   {"force", 3, p.force}};
      output::write_points(s.comm(), fmt::format("{}/{}", s.component_dir(), output::snapshot_name(w)),
                           solver->time(), w, p.size(), p.id, p.species, fields);
      long count = static_cast<long>(p.size()), total = 0;
      MPI_Allreduce(&count, &total, 1, MPI_LONG, MPI_SUM, s.comm());
      s.snapshot_written(w, solver->time(), static_cast<std::size_t>(total),
                         {"position", "velocity", "angular_velocity", "radius", "force"});
    }
  };
  if (w0 == 0) write_output(0);
  for (long w = w0 + 1; w <= s.windows(); ++w) {
    solver->advance(s.window(), substeps);
    coupler::trace().steps = solver->steps();
    write_output(w);
    s.checkpoint(w, [&](const std::string& dir) { solver->save(dir); });
    s.window_done(w);
  }
}

}  // namespace coflow::particles
