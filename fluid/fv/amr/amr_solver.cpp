#include "fluid/fv/amr/amr_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "fluid/fv/amr/composite_output.hpp"
#include "fluid/fv/amr/refinement_criteria.hpp"
#include "fluid/fv/fv_solver.hpp"
#include "fluid/fv/scheme.hpp"
#include "fluid/fv/turbulence/wall_distance.hpp"
#include "fluid/grid/cell_fields.hpp"
#include "immersed/ibm/params.hpp"

namespace coflow::fluid::fv::amr {

AmrFvSolver::AmrFvSolver(const Setup& s, const Params& p)
    : cfg_(s.cfg),
      fluid_(s.params),
      p_(p),
      comm_(s.comm),
      rank_(s.rank),
      decomposition_(s.decomposition),
      owned_(s.decomposition.block(s.rank)) {
  const auto& d = cfg_.domain;
  dims_ = d.cells[2] == 1 ? 2 : 3;
  h_ = d.spacing()[0];
  rho_ = fluid_.density;
  nu_ = fluid_.viscosity;
  boundary_speed_ = fv::boundary_speeds(fluid_, cfg_);
  geometry_.origin = {d.lower[0], d.lower[1], d.lower[2]};
  geometry_.tree_size = h_ * p_.refinement.patch * static_cast<double>(1L << (p_.refinement.levels - 1));
  source_fine_.assign(3 * static_cast<std::size_t>(owned_.volume()), 0.0);
  forest_ = std::make_unique<Forest>(comm_, forest_spec());
  make_flow();
  // Refine on the initial field, one level per pass, then set it again on
  // the leaves made (exact values, not the transfer's), and project.
  for (int pass = 1; pass < p_.refinement.levels; ++pass) {
    set_initial();
    if (!flow_->regrid(marks())) break;
    ++regrids_;
    after_regrid();
  }
  set_initial();
  flow_->project_initial();
}

// Where the time went (rank 0's clock): the steps, the regrids' share of
// steps and regrids together (issue 25's target: at most 10 %), and the
// cells updated per second over both.
AmrFvSolver::~AmrFvSolver() {
  const double total = step_seconds_ + regrid_seconds_;
  if (rank_ != 0 || steps_ == 0 || total <= 0) return;
  log::info("fv (refinement): {} steps in {:.3f} s, {} regrids in {:.3f} s ({:.1f} % of both); {:.0f} cells on "
            "average, {:.4g} cell-steps per second",
            steps_, step_seconds_, regrids_, regrid_seconds_, 100 * regrid_seconds_ / total,
            cell_steps_ / static_cast<double>(steps_), cell_steps_ / total);
}

ForestSpec AmrFvSolver::forest_spec() const {
  ForestSpec spec;
  spec.dims = dims_;
  for (int a = 0; a < 3; ++a) {
    const auto A = static_cast<std::size_t>(a);
    spec.trees[A] = a < dims_ ? static_cast<int>(p_.refinement.base_cells(cfg_, a) / p_.refinement.patch) : 1;
    spec.periodic[A] = a < dims_ && cfg_.domain.periodic[a];
  }
  spec.max_level = p_.refinement.levels - 1;
  spec.patch = p_.refinement.patch;
  spec.components = components();
  spec.positive_from = turbulence_first();  // k, epsilon, nu_t (where kept)
  return spec;
}

// The boundaries of fluid.boundaries (the checks of fluid/schema.cpp keep
// out what the composite flow has not: ramps, a pressure other than the
// reference). Outflow and pressure faces are both outlets, p = 0 and
// du/dn = 0.
void AmrFvSolver::make_flow() {
  flow_ = std::make_unique<CompositeFlow>(*forest_, geometry_, nu_,
                                          IjSystem::Options{p_.tolerance, p_.max_iterations});
  flow_->set_implicit_diffusion(p_.refinement.diffusion == "implicit");
  const auto& d = cfg_.domain;
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2;
    if (a >= dims_ || d.periodic[a]) continue;
    const BoundaryParams b = fluid_.boundary(f, cfg_);
    if (b.type == "symmetry") {
      flow_->set_symmetry(f);
    } else if (b.type == "pressure" || b.type == "outflow") {
      flow_->set_outlet(f);
    } else if (b.type == "velocity") {
      const std::array<double, 3> v{b.value.values[0], b.value.values[1], dims_ == 3 ? b.value.values[2] : 0.0};
      CompositeFlow::Inflow given = [this, b, v, f](const std::array<double, 3>& x) {
        double s[3];
        for (int e = 0; e < 3; ++e)
          s[e] = (x[static_cast<std::size_t>(e)] - cfg_.domain.lower[e]) /
                 (cfg_.domain.upper[e] - cfg_.domain.lower[e]);
        const double k = b.profile_factor(f, s, cfg_);
        return std::array<double, 3>{k * v[0], k * v[1], k * v[2]};
      };
      // No normal velocity: a wall, moving along itself (a lid), whatever its
      // profile (as fv and fv-reference take it); else an inlet.
      if (v[static_cast<std::size_t>(a)] != 0.0)
        flow_->set_inlet(f, std::move(given));
      else if (b.profile == "uniform")
        flow_->set_wall_velocity(f, v);
      else
        flow_->set_wall_velocity(f, std::move(given));
    }
  }
  view_ = std::make_unique<UniformView>(flow_->grid(), decomposition_, rank_);
  apply_source();
  if (!fluid_.turbulence.on) return;
  flow_->set_eddy_viscosity(turbulence_first() + 2);
  turbulence_ =
      std::make_unique<CompositeTurbulence>(*flow_, *forest_, fluid_.turbulence, nu_, turbulence_first(),
                                            std::array<double, 3>{d.lower[0], d.lower[1], d.lower[2]},
                                            std::array<double, 3>{d.upper[0], d.upper[1], d.upper[2]},
                                            IjSystem::Options{p_.tolerance, p_.max_iterations});
  set_turbulence_inlets();
}

// k and epsilon entering through each face: its values, its tables at the
// point, or from its intensity and the inlet's speed beside the point (the
// face's velocity and profile factor there; the adaptive grid's faces have
// no ramp and no t).
void AmrFvSolver::set_turbulence_inlets() {
  std::array<BoundaryParams, 6> faces;
  for (int f = 0; f < 6; ++f) faces[static_cast<std::size_t>(f)] = fluid_.boundary(f, cfg_);
  turbulence_->set_inlets(
      [this, faces, inlets = fluid_.inlet_turbulence(cfg_)](int f, const std::array<double, 3>& x) {
        double speed = 0.0;
        if (inlets.from_speed(f)) {
          const BoundaryParams& b = faces[static_cast<std::size_t>(f)];
          double s[3];
          for (int e = 0; e < 3; ++e)
            s[e] = (x[static_cast<std::size_t>(e)] - cfg_.domain.lower[e]) /
                   (cfg_.domain.upper[e] - cfg_.domain.lower[e]);
          const auto& v = b.value.values;
          const double w = dims_ == 3 ? v[2] : 0.0;
          speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + w * w) * std::abs(b.profile_factor(f, s, cfg_));
        }
        const double point[3] = {x[0], x[1], x[2]};
        return inlets.at(f, speed, point);
      });
}

double& AmrFvSolver::value(std::size_t cell, int q) const {
  const auto per = static_cast<std::size_t>(flow_->grid().cells_per_patch());
  return forest_->data(
      cell / per)[(cell % per) * static_cast<std::size_t>(components()) + static_cast<std::size_t>(q)];
}

void AmrFvSolver::set_initial() {
  const auto& g = flow_->grid();
  for (long c = 0; c < g.local_cells(); ++c) {
    const auto x = g.centre(g.local_cell(c));
    Vec3 u{0, 0, 0};
    double p = 0.0;
    fluid_.initial_state(cfg_, {x[0], x[1], x[2]}, u, p);
    const auto C = static_cast<std::size_t>(c);
    for (int q = 0; q < dims_; ++q) value(C, q) = u[static_cast<std::size_t>(q)];
    // A uniform fluid.initial.pressure sets no level here (the outlets' 0 or
    // the pinned cell does): kept, an implicit first step took it as the old
    // pressure, a jump of P over half a cell at every outlet (fv's first step
    // discards any initial pressure). A field's own (Taylor-Green's) stays.
    value(C, dims_) = (p - fluid_.initial_pressure) / rho_;
  }
  if (turbulence_) turbulence_->set_initial();
}

void AmrFvSolver::after_regrid() {
  view_ = std::make_unique<UniformView>(flow_->grid(), decomposition_, rank_);
  apply_source();
  if (turbulence_) turbulence_->after_regrid();
  if (markers_) make_forcing();
}

void AmrFvSolver::apply_source() {
  view_->to_cells(source_fine_, 3, source_cells_);
  const bool body = fluid_.body_force[0] != 0 || fluid_.body_force[1] != 0 || fluid_.body_force[2] != 0;
  const auto n = static_cast<std::size_t>(flow_->grid().local_cells());
  std::vector<std::vector<double>> a(static_cast<std::size_t>(dims_), std::vector<double>(n, 0.0));
  bool any = body;
  for (std::size_t q = 0; q < a.size(); ++q)
    for (std::size_t c = 0; c < n; ++c) {
      a[q][c] = (source_cells_[3 * c + q] + fluid_.body_force[q]) / rho_;
      any = any || source_cells_[3 * c + q] != 0.0;
    }
  flow_->set_source(any ? std::move(a) : std::vector<std::vector<double>>{});
}

void AmrFvSolver::set_source(std::span<const double> force_density) {
  source_fine_.assign(force_density.begin(), force_density.end());
  apply_source();
}

std::vector<int> AmrFvSolver::marks() {
  const auto& g = flow_->grid();
  const int scratch = dims_ + 1;
  std::vector<std::vector<int>> all;
  for (const auto& c : p_.refinement.criteria) {
    if (c.kind == "vorticity") {
      flow_->vorticity(scratch);
      all.push_back(mark_by_magnitude(*forest_, scratch, c.refine_above, c.coarsen_below));
    } else if (c.kind == "k") {
      all.push_back(mark_by_magnitude(*forest_, turbulence_first(), c.refine_above, c.coarsen_below));
    } else if (c.kind == "walls") {
      all.push_back(mark_near_walls(g, c.distance));
    } else if (c.kind == "box") {
      all.push_back(mark_in_box(g, {c.lower.values[0], c.lower.values[1], c.lower.values[2]},
                                {c.upper.values[0], c.upper.values[1], c.upper.values[2]}));
    } else if (c.kind == "bodies") {
      if (markers_) all.push_back(mark_at_points(g, marker_reach()));
    } else if (c.kind == "particles") {  // where the particles' source is: |f| > 0
      for (std::size_t k = 0; k < static_cast<std::size_t>(g.local_cells()); ++k) {
        const double* f = &source_cells_[3 * k];
        value(k, scratch) = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      }
      all.push_back(mark_by_magnitude(*forest_, scratch, 0.0, std::numeric_limits<double>::min()));
    }
  }
  if (all.empty()) return std::vector<int>(forest_->leaves().size(), 0);  // bodies before their markers: keep
  return combine_marks(all);
}

std::vector<std::array<double, 3>> AmrFvSolver::marker_reach() const {
  std::vector<std::array<double, 3>> points;
  const double w = 2.5 * h_;
  const int nz = dims_ == 3 ? 3 : 1;
  for (const auto& m : markers_->markers)
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
          points.push_back({m.x[0] + (i - 1) * w, m.x[1] + (j - 1) * w, m.x[2] + (dims_ == 3 ? (k - 1) * w : 0.0)});
  return points;
}

void AmrFvSolver::regrid() {
  if (flow_->regrid(marks())) ++regrids_;
  after_regrid();  // the leaves' order may have changed with the partition
}

double AmrFvSolver::stable_step() {
  double umax[4] = {0, 0, 0, 0};  // and 1 where a value is not finite
  const auto u = cell_values(0, dims_, 1.0);
  const auto D = static_cast<std::size_t>(dims_);
  for (std::size_t k = 0; k < u.size(); ++k) {
    const double a = std::abs(u[k]);
    if (!(a <= std::numeric_limits<double>::max())) umax[3] = 1;
    umax[k % D] = std::max(umax[k % D], a);
  }
  MPI_Allreduce(MPI_IN_PLACE, umax, 4, MPI_DOUBLE, MPI_MAX, comm_);
  velocity_scale_ = std::max({umax[0], umax[1], umax[2]});
  if (umax[3] > 0)
    throw std::runtime_error(fmt::format("fv (refinement): the velocity is not finite at t = {:.6g} s (step {}); "
                                         "lower fluid.fv.cfl or fluid.fv.max_step",
                                         time_, steps_));
  if (first_window_) fv::raise_to(umax, boundary_speed_, {0.0, 0.0, 0.0});  // a lid, an inlet at the start
  double rate = 0.0;  // seed 003 eq. 4.1 on the finest cells
  for (int a = 0; a < dims_; ++a) rate += umax[a] / h_;
  double limit = rate > 0 ? p_.cfl / rate : std::numeric_limits<double>::infinity();
  // Heun's method is stable for explicit diffusion up to nu dt / h^2 = 1 / (2 d): half of it. With
  // central advection its amplification is |G|^2 = 1 + C^4 / 4 - (damping by diffusion), so the
  // diffusion number must stay above about C^4 / 16: dt <= (16 nu h^2 / U^4)^(1/3), U = sum |u_d|.
  if (nu_ > 0 && p_.refinement.diffusion != "implicit")
    limit = std::min(limit, h_ * h_ / (4.0 * dims_ * nu_));
  // With k-epsilon every cell is damped by nu + nu_t: the smallest nu_t counts.
  const double damping = nu_ + (turbulence_ ? turbulence_->smallest_eddy_viscosity() : 0.0);
  const double speed = umax[0] + umax[1] + umax[2];
  if (speed > 0) limit = std::min(limit, std::cbrt(16.0 * damping * h_ * h_ / std::pow(speed, 4)));
  if (p_.max_step > 0) limit = std::min(limit, p_.max_step);
  return limit;
}

void AmrFvSolver::advance(double window) {
  first_window_ = steps_ == 0;
  window_steps_ = 0;
  poisson_iterations_ = 0;
  turbulence_substeps_ = 0;
  fv::step_window(time_, dt_prev_, window, [this] { return stable_step(); }, [this](double dt, double t) {
    const double start = MPI_Wtime();
    flow_->step(dt);
    if (turbulence_) {
      turbulence_->step(dt);
      turbulence_substeps_ = std::max(turbulence_substeps_, turbulence_->last_substeps());
    }
    const double stepped = MPI_Wtime();
    step_seconds_ += stepped - start;
    cell_steps_ += static_cast<double>(flow_->grid().global_cells());
    time_ = t;
    dt_prev_ = last_dt_ = dt;
    ++steps_;
    ++window_steps_;
    poisson_iterations_ = std::max(poisson_iterations_, flow_->last_iterations());
    if (steps_ % p_.refinement.every == 0) {
      regrid();
      regrid_seconds_ += MPI_Wtime() - stepped;
    }
  });
}

std::vector<double> AmrFvSolver::cell_values(int first, int count, double scale) const {
  const auto n = static_cast<std::size_t>(count);
  std::vector<double> v(static_cast<std::size_t>(flow_->grid().local_cells()) * n);
  for (std::size_t k = 0; k < v.size() / n; ++k)
    for (std::size_t q = 0; q < n; ++q) v[k * n + q] = scale * value(k, first + static_cast<int>(q));
  return v;
}

// Only the fields asked for cross to the uniform grid (one all-to-all each).
std::vector<output::GridField> AmrFvSolver::fields(const config::StringList& names) {
  const auto asked = [&](const char* n) { return std::find(names.begin(), names.end(), n) != names.end(); };
  const auto N = static_cast<std::size_t>(owned_.volume());
  out_u_.assign(3 * N, 0.0);
  out_p_.assign(N, 0.0);
  out_div_.assign(N, 0.0);
  if (asked("velocity")) {
    const auto u = cell_values(0, dims_, 1.0);
    const auto D = static_cast<std::size_t>(dims_);
    std::vector<double> u3(3 * (u.size() / D), 0.0);
    for (std::size_t k = 0; k < u.size(); ++k) u3[3 * (k / D) + k % D] = u[k];
    view_->to_uniform(u3, 3, out_u_);
  }
  if (asked("pressure")) view_->to_uniform(cell_values(dims_, 1, rho_), 1, out_p_);
  if (asked("divergence")) view_->to_uniform(flow_->divergence(), 1, out_div_);
  out_rho_.assign(N, rho_);
  out_zero_.assign(N, 0.0);  // k, epsilon, nu_t, y_plus without the turbulence model
  if (!turbulence_)
    return FvSolver::named_fields(
        names, {out_u_, out_p_, out_rho_, out_div_, out_zero_, out_zero_, out_zero_, out_zero_});
  const char* turbulent[] = {"k", "epsilon", "nu_t"};
  for (int q = 0; q < 3; ++q) {
    auto& out = out_turbulence_[static_cast<std::size_t>(q)];
    out.assign(N, 0.0);
    if (asked(turbulent[q])) view_->to_uniform(cell_values(turbulence_first() + q, 1, 1.0), 1, out);
  }
  auto& y_plus = out_turbulence_[3];
  y_plus.assign(N, 0.0);
  if (asked("y_plus")) view_->to_uniform(turbulence_->y_plus(), 1, y_plus);
  return FvSolver::named_fields(names, {out_u_, out_p_, out_rho_, out_div_, out_turbulence_[0],
                                        out_turbulence_[1], out_turbulence_[2], y_plus});
}

// The fields asked for, as fields() gives them on the uniform grid (pressure
// in Pa; k, epsilon, nu_t and y_plus 0 without the turbulence model), then
// the vorticity (the refinement's criterion) and each cell's level.
void AmrFvSolver::write_levels(const std::string& dir, const std::string& stem, double time, long step,
                               const config::StringList& names) {
  const auto cells = static_cast<std::size_t>(flow_->grid().local_cells());
  std::vector<CompositeField> out;
  for (const auto& name : names) {
    if (name == "velocity") out.push_back({name, 0, dims_});
    if (name == "pressure") out.push_back({name, dims_, 1, rho_});
    if (name == "density") out.push_back({name, 0, 1, 1.0, std::vector<double>(cells, rho_)});
    if (name == "divergence") out.push_back({name, 0, 1, 1.0, flow_->divergence()});
    const int q = name == "k" ? 0 : name == "epsilon" ? 1 : name == "nu_t" ? 2 : -1;
    if (q >= 0 && turbulence_) out.push_back({name, turbulence_first() + q, 1});
    if (name == "y_plus" && turbulence_) out.push_back({name, 0, 1, 1.0, turbulence_->y_plus()});
    if ((q >= 0 || name == "y_plus") && !turbulence_)
      out.push_back({name, 0, 1, 1.0, std::vector<double>(cells, 0.0)});
  }
  flow_->vorticity(dims_ + 1);
  out.push_back({"vorticity", dims_ + 1, 1});
  write_composite(flow_->grid(), dir, stem, time, step, out);
}

// Mass, momentum and kinetic energy over the leaf cells (each of its own
// volume); then the window's steps, last step, most Poisson iterations of a
// step, the largest face divergence, the cells and the regrids so far.
Diagnostics AmrFvSolver::diagnostics() {
  const auto& g = flow_->grid();
  const auto u = cell_values(0, dims_, 1.0);
  const auto D = static_cast<std::size_t>(dims_);
  Diagnostics d;
  for (std::size_t k = 0; k < static_cast<std::size_t>(g.local_cells()); ++k) {
    const double m = rho_ * std::pow(g.spacing(g.local_cell(static_cast<long>(k)).level), dims_) *
                     (dims_ == 2 ? cfg_.domain.upper[2] - cfg_.domain.lower[2] : 1.0);
    double u2 = 0.0;
    for (std::size_t q = 0; q < D; ++q) {
      d.momentum[q] += m * u[k * D + q];
      u2 += u[k * D + q] * u[k * D + q];
    }
    d.mass += m;
    d.kinetic_energy += 0.5 * m * u2;
    d.max_velocity = std::max(d.max_velocity, std::sqrt(u2));
  }
  FvSolver::reduce(d, comm_);
  d.extra = {static_cast<double>(window_steps_),      last_dt_, static_cast<double>(poisson_iterations_),
             flow_->face_divergence(),                static_cast<double>(g.global_cells()),
             static_cast<double>(regrids_)};
  if (turbulence_) {  // fv's columns (y_plus from the cells' gradients), then the most sub-steps of k and
                      // epsilon in a step
    const auto sum = turbulence_->totals();
    const auto nut = turbulence_->largest_eddy_viscosity();
    const auto y_plus = turbulence_->y_plus();
    double y_plus_max = y_plus.empty() ? 0.0 : *std::max_element(y_plus.begin(), y_plus.end());
    MPI_Allreduce(MPI_IN_PLACE, &y_plus_max, 1, MPI_DOUBLE, MPI_MAX, comm_);
    d.extra.insert(d.extra.end(),
                   {sum[0] / sum[2], sum[1] / sum[2], *std::max_element(nut.begin(), nut.end()), y_plus_max,
                    static_cast<double>(turbulence_substeps_)});
  }
  return d;
}

std::vector<output::Series::Column> AmrFvSolver::series_columns() const {
  std::vector<output::Series::Column> c{
      {"steps", "1"}, {"dt", "s"},     {"poisson_iterations", "1"}, {"max_divergence", "1/s"},
      {"cells", "1"}, {"regrids", "1"}};
  if (fluid_.turbulence.on) {
    const auto t = FvSolver::turbulence_columns("turbulence_substeps");
    c.insert(c.end(), t.begin(), t.end());
  }
  return c;
}

// What a checkpoint's forest must share with the run that loads it.
static std::string spec_text(const ForestSpec& s) {
  return fmt::format("{}D, {}x{}x{} trees, levels {} to {}, patches of {} cells, {} values a cell", s.dims,
                     s.trees[0], s.trees[1], s.trees[2], s.min_level, s.max_level, s.patch, s.components);
}

// The periodic axes, which p4est keeps in the forest's connectivity.
static std::string periodic_text(const ForestSpec& s) {
  std::string axes;
  for (int a = 0; a < s.dims; ++a)
    if (s.periodic[static_cast<std::size_t>(a)]) axes += std::string(axes.empty() ? "" : " ") + "xyz"[a];
  return "periodic along " + (axes.empty() ? std::string("no axis") : axes);
}

// The forest and the flow (composite_flow.hpp), then the solver's own state
// in dir/amr.txt: steps, time, last step (hexadecimal floats: exact),
// regrids, the last window's steps.
void AmrFvSolver::save(const std::string& dir) {
  flow_->save(dir);
  grid::save_text(comm_, dir + "/amr.txt",
                  fmt::format("{} {:a} {:a} {} {}\n{}\n{}\n", steps_, time_, dt_prev_, regrids_,
                              window_steps_, spec_text(forest_spec()), periodic_text(forest_spec())));
}

// The steps and time come from the checkpoint: the driver's count is of
// windows (fv's steps vary), and the regrids fall every `every` steps.
void AmrFvSolver::load(const std::string& dir, long, double) {
  std::ifstream f(dir + "/amr.txt");
  std::string time_text, dt_text;
  if (!(f >> steps_ >> time_text >> dt_text >> regrids_ >> window_steps_))
    throw std::runtime_error("fv (refinement): " + dir + "/amr.txt is missing or unreadable");
  auto number = [](const std::string& t) {  // the whole text, or NaN
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    return end == t.c_str() + t.size() ? v : std::nan("");
  };
  time_ = number(time_text);
  dt_prev_ = number(dt_text);
  if (!(std::isfinite(time_) && time_ >= 0 && std::isfinite(dt_prev_) && dt_prev_ >= 0))
    throw std::runtime_error(
        fmt::format("fv (refinement): {}/amr.txt holds a time {} or a last step {} that is not "
                    "a finite number of zero or more: the checkpoint is damaged",
                    dir, time_text, dt_text));
  // The forest must be this run's (p4est aborts the job on another patch or
  // field count, and another brick misplaces the leaves): a checkpoint from
  // before 2026-12-05 does not say, and is taken as it is.
  // Nor may its periodic axes differ (a stencil would wrap where p4est keeps
  // no ghosts): a checkpoint from before 2026-12-06 does not say.
  std::string saved, periodic;
  std::getline(f >> std::ws, saved);
  std::getline(f >> std::ws, periodic);
  if (const std::string mine = spec_text(forest_spec()); !saved.empty() && saved != mine)
    throw std::runtime_error(fmt::format(
        "fv (refinement): {}/forest.p4est holds an adaptive grid of {}, but this run's is {}: restart with "
        "the "
        "domain.cells, fluid.fv.refinement (levels, patch) and fluid.turbulence of the run that wrote it",
        dir, saved, mine));
  if (const std::string mine = periodic_text(forest_spec()); !periodic.empty() && periodic != mine)
    throw std::runtime_error(
        fmt::format("fv (refinement): {}/forest.p4est holds an adaptive grid {}, but this "
                    "run's is {}: restart with the domain.periodic of the run that wrote it",
                    dir, periodic, mine));
  flow_.reset();
  view_.reset();
  forest_ = std::make_unique<Forest>(comm_, forest_spec(), dir + "/forest.p4est");
  make_flow();
  if (markers_) install_forcing();
  flow_->load(dir);
  if (turbulence_) turbulence_->check_loaded(dir + "/forest.p4est");
}

// The flow is forced from the first markers on (its implicit step then
// leaves out the incremental pressure: composite_flow.cpp).
void AmrFvSolver::install_forcing() {
  flow_->set_forcing([this](CompositeFlow::Field& u, double dt, int stage) { force(u, dt, stage); });
}

// The first markers: the leaves around them refine to the finest level
// (one level per pass), then the forcing is built on it. Every set (a
// moving body's each window) is checked against the leaves.
void AmrFvSolver::set_markers(ibm::MarkerSet markers) {
  const bool first = !markers_;
  markers_ = std::make_unique<ibm::MarkerSet>(std::move(markers));
  if (first) install_forcing();
  // (A restarted run's forest is refined already: no pass, bit for bit.)
  for (int pass = 1; first && steps_ == 0 && pass < p_.refinement.levels; ++pass)
    if (flow_->regrid(marks())) {
      ++regrids_;
      view_ = std::make_unique<UniformView>(flow_->grid(), decomposition_, rank_);
      apply_source();
      if (turbulence_) turbulence_->after_regrid();
    }
  if (turbulence_)  // the bodies are walls too (seed 003 §3.1.2)
    turbulence_->set_body_distance(
        [body = std::make_shared<fv::BodyDistance>(*markers_, fv::BodyDistance::grid_of(cfg_))](
            const std::array<double, 3>& x) { return (*body)(x); });
  make_forcing();
}

// The forcing on the finest cells: a point of the finest grid is a local
// cell where a finest leaf cell of this rank is there, else nobody's. Every
// point a marker's kernel reaches must be one somewhere, or the marker would
// lose part of its stencil: checked on the points of marker_reach(). The
// stencils are built again on the current leaves (the loads so far stay).
void AmrFvSolver::make_forcing() {
  const int finest = p_.refinement.levels - 1;
  long coarse = 0;
  for (const auto& x : marker_reach()) {
    long c = 0;
    if (flow_->grid().locate(x, &c) && flow_->grid().local_cell(c).level < finest) ++coarse;
  }
  MPI_Allreduce(MPI_IN_PLACE, &coarse, 1, MPI_LONG, MPI_SUM, comm_);
  if (coarse > 0)
    throw std::runtime_error(fmt::format(
        "fv (refinement): {} points within 2.5 cells of the immersed boundary's markers lie on a coarser level "
        "than the finest: add `bodies` to fluid.fv.refinement.criteria (it refines there), or regrid more often",
        coarse));
  if (!ibm_) {
    std::array<bool, 3> periodic{};
    for (int a = 0; a < dims_; ++a) periodic[static_cast<std::size_t>(a)] = cfg_.domain.periodic[a];
    auto index = [this, finest](const std::array<long, 3>& at) -> long {
      const auto& g = flow_->grid();
      long id = 0;
      if (g.cover(finest, at, &id) != CompositeGrid::Cover::leaf) return -1;
      id -= g.first_cell();
      return id >= 0 && id < g.local_cells() ? id : -1;
    };
    auto grid = ibm::DirectForcing::collocated(immersed::grid_geometry(cfg_.domain), periodic, index);
    ibm_ = std::make_unique<ibm::DirectForcing>(std::move(grid), immersed::read_ibm_params(cfg_).forcing(), comm_);
  }
  ibm_->set_markers(*markers_);
}

// In each Heun stage, before its projection: u forced toward the markers'
// velocities at the step's end. A change dU in stage s enters the step with
// the weight w_s (composite_flow.hpp: 1/2 and 1 with explicit diffusion, 1
// and 1 implicit), so the loads take the factors 2 w_s rho / dt: their mean
// over the two calls is the step's force, rho (w_0 dU_0 + w_1 dU_1) dV / dt
// (eq. 4.8).
void AmrFvSolver::force(CompositeFlow::Field& u, double dt, int stage) {
  if (!ibm_ || ibm_->empty()) return;
  std::array<double*, 3> v{nullptr, nullptr, nullptr};
  for (std::size_t q = 0; q < u.size(); ++q) v[q] = u[q].data();
  ibm_->apply(v, time_ + dt, velocity_scale_, 2.0 * flow_->stage_weight(stage) * rho_ / dt, dt);
}

std::vector<double> AmrFvSolver::take_body_loads() { return ibm_ ? ibm_->take_report() : std::vector<double>{}; }

}  // namespace coflow::fluid::fv::amr
