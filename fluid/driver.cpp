#include "fluid/driver.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>

#include "coflow/exchange.hpp"
#include "coflow/impulse_series.hpp"
#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "coflow/protocol.hpp"
#include "coflow/run_config.hpp"
#include "coflow/window_loop.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/probes.hpp"
#include "fluid/schema.hpp"
#include "immersed/ibm/link.hpp"

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
  const std::string& variant = cfg.component("fluid").variant;
  const std::string& section = find_variant(variant_schemas(), variant).params_section;
  YAML::Node sub = section.empty() ? YAML::Node() : cfg.resolved["fluid"][section];
  config::Reader r(sub, cfg.file, "fluid." + section);
  std::unique_ptr<FluidSolver> solver = registry().at(variant).create(setup, r);
  r.check();
  return solver;
}

namespace {

void write_series(output::Series& series, double t, const Diagnostics& d) {
  const double row[] = {t, d.mass, d.momentum[0], d.momentum[1], d.momentum[2], d.kinetic_energy,
                        d.max_velocity, d.max_mach};
  std::vector<double> values(std::begin(row), std::end(row));
  values.insert(values.end(), d.extra.begin(), d.extra.end());
  series.row(values);
}

// The fluid's part of each window: with psm, the covered cells with their
// solid fraction and velocity arrive before the step and the force the fluid
// exerted on the solid in them goes back after it; with point, the fluid's
// velocity, k and epsilon go out at the window's start (ghost layer 2 for the
// immersed side's interpolation and vorticity) and the particles' momentum
// source of the window comes back before the step.
class FluidWindows final : public coupler::WindowParts {
 public:
  FluidWindows(coupler::Session& s, std::unique_ptr<FluidSolver> solver, long per_window)
      : s_(s), cfg_(s.config()), solver_(std::move(solver)), per_window_(per_window), owned_(solver_->owned()),
        probes_(cfg_, s.decomposition(), s.rank(), s.comm()) {
    psm_ = s.has_partner("immersed") && cfg_.component("immersed").variant == "psm";
    point_ = s.has_partner("immersed") && config::point_coupling(cfg_);
    ibm_ = s.has_partner("immersed") && cfg_.component("immersed").variant == "ibm";
    if (psm_ || point_) open_exchanges();
    // A window given within 1e-6 of a whole number of steps (whole_steps):
    // the source, the particles' impulse over the window, is applied for
    // per_window steps of dt, so it takes window / (per_window dt); the psm
    // force, the mean over those steps, which the particles apply over the
    // window, takes the inverse. The momentum they exchange stays equal and
    // opposite.
    const double dt = solver_->time_step();
    if (dt > 0 && std::abs(s.window() - per_window * dt) > 1e-12 * s.window())
      source_scale_ = s.window() / (static_cast<double>(per_window) * dt);
  }

  void start(long w0) override {
    if (w0 > 0) solver_->load(s_.restart_dir(), w0 * per_window_, w0 * s_.window());
    if (s_.rank() == 0) {
      std::vector<output::Series::Column> columns{{"time", "s"},         {"mass", "kg"},
                                                  {"momentum_x", "kg m/s"}, {"momentum_y", "kg m/s"},
                                                  {"momentum_z", "kg m/s"}, {"kinetic_energy", "J"},
                                                  {"max_velocity", "m/s"},  {"max_mach", "1"}};
      const auto extra = solver_->series_columns();
      columns.insert(columns.end(), extra.begin(), extra.end());
      const FluidParams params = read_params(cfg_);
      if (params.turbulence.on && params.turbulence.wall == "two-layer")
        for (std::size_t k = 0; k < extra.size(); ++k)
          if (extra[k].name == "y_plus_max") y_plus_column_ = static_cast<long>(k);
      series_ = output::Series(s_.output_dir() + "/series/fluid.csv", columns, w0 > 0);
    }
    if (s_.rank() == 0 && !probes_.empty()) {
      std::vector<output::Series::Column> columns{{"time", "s"}};
      for (const auto& c : probes_.columns()) columns.push_back({c, c.ends_with("_p") || c.ends_with("_p_from") ||
                                                                           c.ends_with("_p_to") || c.ends_with("_dp")
                                                                       ? "Pa"
                                                                       : "m/s"});
      probes_series_ = output::Series(s_.output_dir() + "/series/probes.csv", columns, w0 > 0);
    }
    if (solver_->keeps_wall_impulse()) walls_ = wall_series(w0);
    // With psm the initial snapshot waits for the first window's solids, so that it shows them.
    if (w0 == 0 && !psm_) output(0);
  }
  void before_step(long w) override {
    if (psm_) {
      receive_solids();
      if (w == 1) output(0);
    }
    // The markers first: immersed broadcasts them at the start of its window,
    // before the point exchanges of particles beside the bodies (a large
    // broadcast completes only when both sides are in it).
    if (ibm_ && !markers_last_ && ibm::receive_markers(s_.partner("immersed"), markers_, markers_last_))
      solver_->set_markers(ibm::MarkerSet::unpack(markers_));
    if (point_) {
      send_flow();
      receive_source();
    }
  }
  void step(long) override {
    solver_->advance(s_.window());
    coupler::trace().steps = solver_->steps();
    if (walls_) walls_->add(solver_->take_wall_impulse());
  }
  void after_step(long) override {
    if (psm_) send_solid_force();
    if (ibm_) {
      const std::vector<double> loads = solver_->take_body_loads();
      if (s_.rank() == 0) ibm::send_loads(s_.partner("immersed"), loads);
    }
  }
  void output(long w) override;
  void save(const std::string& dir) override {
    solver_->save(dir);
    if (walls_) walls_->save(dir);
  }
  void finish() override {
    if (solid_in_) solid_in_->flush();
    if (flow_out_) flow_out_->flush();
  }

 private:
  void open_exchanges();
  std::unique_ptr<coupler::ImpulseSeries> wall_series(long w0);
  void warn_coarse_wall_cells(const Diagnostics& d, double time);
  void receive_solids();
  void send_solid_force();
  void send_flow();
  void receive_source();

  coupler::Session& s_;
  const config::Config& cfg_;
  std::unique_ptr<FluidSolver> solver_;
  long per_window_;
  double source_scale_ = 1.0;  // the window over the time its steps make (1 to 1e-12)
  coupler::Box owned_;
  bool psm_ = false, point_ = false, ibm_ = false;
  std::vector<double> markers_;  // ibm: the last marker message
  bool markers_last_ = false;    // ibm: the markers hold to the end (fixed bodies)
  output::Series series_;
  long y_plus_column_ = -1;  // two-layer k-epsilon: y_plus_max among the series' extra columns
  bool y_plus_warned_ = false;
  Probes probes_;
  output::Series probes_series_;
  std::unique_ptr<coupler::ImpulseSeries> walls_;  // the fluid's force on its wall faces
  std::unique_ptr<coupler::FieldExchange> solid_in_, flow_out_, source_in_;
  std::vector<long> solid_cells_;
  std::vector<double> solid_values_, fraction_, velocity_, wetting_, force_;
  std::vector<double> flow_local_, source_local_, source_owned_;
};

void FluidWindows::output(long w) {
  coupler::Timer t(coupler::trace().io_s);
  // The run's clock, as the other components write it (the solver's own time
  // is n dt, which a window given within 1e-6 of n steps misses by as much).
  const double time = static_cast<double>(w) * s_.window();
  if (s_.series_due(w)) {
    const Diagnostics d = solver_->diagnostics();
    if (s_.rank() == 0) write_series(series_, time, d);
    if (s_.rank() == 0) warn_coarse_wall_cells(d, time);
    s_.set_final("fluid.mass", d.mass);
    s_.set_final("fluid.momentum_x", d.momentum[0]);
    s_.set_final("fluid.momentum_y", d.momentum[1]);
    s_.set_final("fluid.momentum_z", d.momentum[2]);
    s_.set_final("fluid.kinetic_energy", d.kinetic_energy);
    if (walls_) walls_->row(w * s_.window());
    if (!probes_.empty()) {
      std::vector<double> row{time};
      const std::vector<double> values = probes_.sample(*solver_);
      row.insert(row.end(), values.begin(), values.end());
      if (s_.rank() == 0) probes_series_.row(row);
    }
  }
  if (s_.snapshot_due(w)) {
    const auto fields = solver_->fields(cfg_.run.output.fields);
    const auto& c = cfg_.domain.cells;
    output::write_grid(s_.comm(), fmt::format("{}/{}", s_.component_dir(), s_.snapshot_file(w)), time, w,
                       {c[0], c[1], c[2]}, owned_, owned_, fields);
    const std::string stem = s_.snapshot_file(w);
    solver_->write_levels(s_.component_dir(), stem.substr(0, stem.size() - 3) + "_levels", time, w,
                          cfg_.run.output.fields);
    std::vector<std::string> names;
    for (const auto& f : fields) names.push_back(f.name);
    s_.snapshot_written(w, 0, names);
  }
}

// The two-layer model resolves the viscous sublayer with its one-equation
// layer (seed 003 §3.1.2.1: the first cells at y+ of about 1); with the
// cells next to a wall beyond the sublayer (y+ > 5, Pope 2000 §7.1.4) the
// wall's shear and the near-wall epsilon are not resolved. Warned once
// (rank 0), at the first series row after the start that shows it.
void FluidWindows::warn_coarse_wall_cells(const Diagnostics& d, double time) {
  if (y_plus_column_ < 0 || y_plus_warned_ || !(time > 0)) return;  // not the initial state's shear
  const double y_plus = d.extra.at(static_cast<std::size_t>(y_plus_column_));
  if (!(y_plus > 5.0)) return;
  y_plus_warned_ = true;
  log::warn(
      "fluid: the cells next to a wall reach y+ = {:.3g} at t = {:.6g} s; fluid.turbulence.wall: two-layer "
      "resolves the viscous sublayer (y+ < 5) and wants the first cells at y+ of about 1 (seed 003 "
      "§3.1.2.1): refine the grid near the walls, or take wall: log-law (first cells at y+ 30 to 100) "
      "(warned once; series/fluid.csv's y_plus_max follows it)",
      y_plus, time);
}

// series/fluid_walls.csv: the faces that are walls for the fluid.
std::unique_ptr<coupler::ImpulseSeries> FluidWindows::wall_series(long w0) {
  const FluidParams params = read_params(cfg_);
  std::vector<std::string> names;
  std::vector<std::size_t> slots;
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2;
    if (cfg_.domain.periodic[a] || cfg_.domain.cells[a] == 1 || params.boundary(f, cfg_).type != "wall") continue;
    names.push_back(face_names()[f]);
    slots.push_back(static_cast<std::size_t>(f));
  }
  // Interior solids (fluid.solids), one each: solid1 is fluid.solids[0].
  const std::size_t solids = params.solids.size();
  for (std::size_t n = 0; n < solids; ++n) {
    names.push_back(fmt::format("solid{}", n + 1));
    slots.push_back(6 + n);
  }
  return std::make_unique<coupler::ImpulseSeries>(s_, "fluid_walls", std::move(names), std::move(slots), 6 + solids,
                                                  w0);
}

void FluidWindows::open_exchanges() {
  using coupler::FieldExchange;
  const auto other = s_.decomposition_of("immersed", s_.partner_ranks("immersed"));
  auto open = [&](FieldExchange::Role role, coupler::FieldSpec spec, int tag) {
    return std::make_unique<FieldExchange>(s_.partner("immersed"), role, s_.decomposition(), s_.rank(), other, spec,
                                           tag);
  };
  if (psm_) {
    solid_in_ = open(FieldExchange::Role::receiver,
                     {"solid", protocol::solid_values(config::two_phase_fluid(s_.config())),
                      coupler::Transfer::consistent, 0},
                     protocol::kTagSolid);
  }
  if (point_) {
    flow_out_ = open(FieldExchange::Role::sender, {"flow", 5, coupler::Transfer::consistent, 2}, protocol::kTagFlow);
    source_in_ = open(FieldExchange::Role::receiver, {"source", 3, coupler::Transfer::conservative, 1},
                      protocol::kTagSource);
    flow_local_.assign(flow_out_->local_size(), 0.0);
    source_local_.assign(source_in_->local_size(), 0.0);
  }
}

void FluidWindows::receive_solids() {
  solid_in_->receive_sparse(solid_cells_, solid_values_);
  const std::size_t n = solid_cells_.size();
  const int nc = solid_in_->spec().components;  // one fluid: no wetting sent (0 here: no interface to wet)
  fraction_.resize(n);
  velocity_.resize(3 * n);
  wetting_.resize(n);
  for (std::size_t c = 0; c < n; ++c) {
    fraction_[c] = solid_values_[nc * c];
    for (int d = 0; d < 3; ++d) velocity_[3 * c + d] = solid_values_[nc * c + 1 + d];
    wetting_[c] = nc == 5 ? solid_values_[nc * c + 4] : 0.0;
  }
  solver_->set_solid(solid_cells_, fraction_, velocity_, wetting_);
}

// The force on the solid in each cell, back to the immersed rank that sent
// the cell, in its order (a reply: no cell indices travel).
void FluidWindows::send_solid_force() {
  solver_->take_solid_force(force_);
  if (source_scale_ != 1.0)
    for (double& f : force_) f /= source_scale_;
  solid_in_->reply_sparse(std::move(force_), 3);  // force_ comes back as another buffer
}

void FluidWindows::send_flow() {
  flow_out_->flush();
  const auto fields = solver_->fields({"velocity", "k", "epsilon"});
  const coupler::Box& o = owned_;
  const long nx = o.extent(0), ny = o.extent(1);
  for (const auto& f : fields) {
    const int first = f.name == "velocity" ? 0 : f.name == "k" ? 3 : 4;
    for (long k = o.lo[2]; k < o.hi[2]; ++k)
      for (long j = o.lo[1]; j < o.hi[1]; ++j)
        for (long i = o.lo[0]; i < o.hi[0]; ++i) {
          const long c = ((k - o.lo[2]) * ny + (j - o.lo[1])) * nx + (i - o.lo[0]);
          const long l = flow_out_->local_index({i, j, k});
          for (int d = 0; d < f.components; ++d) flow_local_[5 * l + first + d] = f.data[f.components * c + d];
        }
  }
  flow_out_->send(flow_local_);
}

void FluidWindows::receive_source() {
  source_in_->receive(source_local_);
  const coupler::Box& o = owned_;
  source_owned_.resize(3 * o.volume());
  std::size_t c = 0;
  for (long k = o.lo[2]; k < o.hi[2]; ++k)
    for (long j = o.lo[1]; j < o.hi[1]; ++j)
      for (long i = o.lo[0]; i < o.hi[0]; ++i, ++c) {
        const long l = source_in_->local_index({i, j, k});
        for (int d = 0; d < 3; ++d) source_owned_[3 * c + d] = source_local_[3 * l + d] * source_scale_;
      }
  solver_->set_source(source_owned_);
}

// The window: a whole number of fluid steps.
long steps_per_window(const config::Config& cfg, double dt, double window) {
  if (dt <= 0) return 1;
  const long n = whole_steps(window, dt);
  if (n == 0)
    throw config::ConfigError({config::Problem{
        cfg.file, 0, 0, "coupling.window",
        fmt::format("must be a whole number of fluid steps ({:.6g} s); got {:.6g} s", dt, window)}});
  return n;
}

}  // namespace

void run(coupler::Session& s) {
  const auto& cfg = s.config();
  if (cfg.component("fluid").variant == "external")
    throw std::runtime_error(
        "fluid.solver is 'external': run your own executable with `coflow run --exe fluid=PATH`");
  const FluidParams params = read_params(cfg);
  FluidSolver::Setup setup{cfg, params, s.decomposition(), s.rank(), s.comm()};
  std::unique_ptr<FluidSolver> solver = make_solver(setup);
  double dt = solver->time_step();
  const double window = s.negotiate_window(dt);
  if (dt > 0 && window < dt * (1 - 1e-12) && cfg.coupling.window.is_auto) {
    // The window was shortened so that snapshots fall at their exact times
    // (coupler::output_window): the fluid takes it as its step.
    log::info("fluid: step {:.6g} s shortened to the window {:.6g} s so that a whole number of steps makes "
              "run.output.every",
              dt, window);
    solver.reset();  // the first solver's memory goes before the second is made
    setup.time_step = window;
    solver = make_solver(setup);
    dt = solver->time_step();
  }
  const long per_window = steps_per_window(cfg, dt, window);
  FluidWindows windows(s, std::move(solver), per_window);
  coupler::run_windows(s, windows);
}

}  // namespace coflow::fluid
