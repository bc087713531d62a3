#include "particles/wall_loads.hpp"
#include "particles/driver.hpp"

#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/finite.hpp"
#include "coflow/window_loop.hpp"
#include "particles/event_log.hpp"
#include "particles/immersed_link.hpp"
#include "particles/particles_interface.hpp"
#include "particles/schema.hpp"

namespace coflow::particles {

namespace {

// The particles' part of each window: sub-steps inside the fluid's window (one
// window per output interval when alone), the exchanges with the immersed
// component, the state check, series, snapshots and event logs.
class ParticleWindows final : public coupler::WindowParts {
 public:
  ParticleWindows(coupler::Session& s, std::unique_ptr<ParticleSolver> solver, const ParticleParams& params,
                  long substeps)
      : s_(s), solver_(std::move(solver)), params_(params), substeps_(substeps) {}

  void start(long w0) override;
  void before_step(long w) override {
    if (link_) link_->before_step(w);
  }
  void step(long) override { solver_->advance(s_.window(), substeps_); }
  void after_step(long w) override {
    check_state();  // before the states go anywhere (parallel-explicit sends the next window's here)
    if (link_) link_->after_step(w);
    walls_->add(solver_->take_wall_impulse());
    coupler::trace().steps = solver_->steps();
  }
  void output(long w) override;
  void save(const std::string& dir) override {
    solver_->save(dir);
    walls_->save(dir);
    events_->save(dir);
    if (link_) link_->save(dir);
  }

 private:
  void check_state();

  coupler::Session& s_;
  std::unique_ptr<ParticleSolver> solver_;
  const ParticleParams& params_;
  long substeps_;
  output::Series series_;
  std::unique_ptr<EventLog> events_;
  std::unique_ptr<ImmersedLink> link_;
  std::unique_ptr<coupler::ImpulseSeries> walls_;
};

void ParticleWindows::start(long w0) {
  if (w0 > 0) solver_->load(s_.restart_dir(), w0 * substeps_, w0 * s_.window());
  if (s_.rank() == 0)
    series_ = output::Series(s_.output_dir() + "/series/particles.csv",
                             {{"time", "s"},
                              {"count", "1"},
                              {"momentum_x", "kg m/s"},
                              {"momentum_y", "kg m/s"},
                              {"momentum_z", "kg m/s"},
                              {"kinetic_energy", "J"},
                              {"collisions", "1"},
                              {"wall_collisions", "1"},
                              {"broken_bonds", "1"},
                              {"rotational_energy", "J"}},
                             w0 > 0);
  walls_ = make_wall_loads(s_, params_, w0);
  const auto& out = s_.config().run.output;
  solver_->record_events(out.collision_events, out.bond_events);
  events_ = std::make_unique<EventLog>(s_, out, params_.point_particles, w0);
  if (s_.has_partner("immersed")) link_ = std::make_unique<ImmersedLink>(s_, *solver_, params_);
  if (link_ && w0 > 0) link_->load(s_.restart_dir());
  if (w0 == 0) output(0);
}

void ParticleWindows::output(long w) {
  if (w > 0 && events_->wanted()) events_->write(solver_->take_events());
  coupler::Timer t(coupler::trace().io_s);
  if (s_.series_due(w)) {
    const ParticleStats st = solver_->stats();
    // The window's end time, not the sum of the sub-steps (whose round-off
    // would differ after a restart, which starts from w x window).
    const double row[] = {w * s_.window(), double(st.count), st.momentum[0], st.momentum[1], st.momentum[2],
                          st.kinetic_energy, double(st.collisions), double(st.wall_collisions),
                          double(st.broken_bonds), st.rotational_energy};
    if (s_.rank() == 0) series_.row(row);
    solver_->write_statistics(s_.output_dir() + "/series");
    walls_->row(w * s_.window());
    s_.set_final("particles.count", double(st.count));
    s_.set_final("particles.kinetic_energy", st.kinetic_energy);
    s_.set_final("particles.broken_bonds", double(st.broken_bonds));
  }
  if (s_.snapshot_due(w)) {
    const ParticleArrays& p = solver_->particles();
    const std::vector<output::PointField> fields{{"position", 3, p.x},       {"velocity", 3, p.v},
                                                 {"angular_velocity", 3, p.w}, {"radius", 1, p.radius},
                                                 {"force", 3, p.force}};
    std::vector<std::string> names;
    for (const auto& sp : params_.species) names.push_back(sp.first);
    // The run's clock, as the series and the other components' snapshots (the
    // solver's sum of sub-steps may differ from it in the last bits).
    output::write_points(s_.comm(), fmt::format("{}/{}", s_.component_dir(), s_.snapshot_file(w)),
                         static_cast<double>(w) * s_.window(), w, p.size(), p.id, p.species, fields, names);
    long count = static_cast<long>(p.size()), total = 0;
    MPI_Allreduce(&count, &total, 1, MPI_LONG, MPI_SUM, s_.comm());
    s_.snapshot_written(w, static_cast<std::size_t>(total),
                       {"position", "velocity", "angular_velocity", "radius", "force"});
  }
}

// Every window, before the state goes anywhere: a particle whose state is not
// finite stops the run here, named, rather than in the fluid later.
void ParticleWindows::check_state() {
  const ParticleArrays& p = solver_->particles();
  const std::string hint =
      params_.point_particles
          ? "the step may be too long for the particles' response time: set particles.time_step: auto"
          : "the step may be too large for the contact stiffness (seed 000 eq. 2.19): lower "
            "particles.time_step_fraction or the stiffness; or a force too large to integrate (the "
            "fluid's on the grains is in series/immersed.csv: check the fluid's density and "
            "the grains' sizes)";
  coupler::check_finite(s_.comm(), {fmt::format("particles ({})", s_.config().component("particles").variant),
                                    "particle", hint},
                        solver_->steps(), solver_->time(),
                        {{"position", p.x}, {"velocity", p.v}, {"angular velocity", p.w}, {"force", p.force}}, 3,
                        p.id);
}

}  // namespace

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
  ParticleSolver::Setup setup{cfg, params, s.decomposition(), s.rank(), s.comm()};
  config::Reader r(YAML::Node(), cfg.file, "particles");
  std::unique_ptr<ParticleSolver> solver = registry().at(info.variant).create(setup, r);

  s.negotiate_window(0.0);
  const long substeps = s.substeps(solver->time_step());
  log::info("particles: step {:.4g} s, {} sub-steps of {:.4g} s per window", solver->time_step(), substeps,
            s.window() / substeps);
  ParticleWindows windows(s, std::move(solver), params, substeps);
  coupler::run_windows(s, windows);
}

}  // namespace coflow::particles
