#include "fluid/fv/fv_solver.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "coflow/log.hpp"
#include "fluid/grid/cell_fields.hpp"

namespace coflow::fluid {

namespace {

constexpr int kGhost = 2;  // the upwind-biased face value reads two cells upstream

fv::StructSystem::Options solver_options(const fv::FvParams& p, const std::string& name) {
  return {p.multigrid == "smg" ? "smg" : "pfmg", p.tolerance, p.max_iterations, name};
}

}  // namespace

FvSolver::FvSolver(const Setup& s, const Params& p)
    : cfg_(s.cfg),
      fluid_(s.params),
      p_(p),
      comm_(s.comm),
      rank_(s.rank),
      ex_(s.decomposition, s.rank, kGhost, 1, s.comm),
      blk_(ex_.block()) {
  const auto& d = cfg_.domain;
  const auto h = d.spacing();
  dims_ = d.cells[2] == 1 ? 2 : 3;
  for (int a = 0; a < 3; ++a) {
    cells_[a] = d.cells[a];
    periodic_[static_cast<std::size_t>(a)] = d.periodic[a] || d.cells[a] == 1;
    h_[a] = h[a];
    inv_h_[a] = 1.0 / h[a];
  }
  nu_ = fluid_.viscosity;
  rho_ = fluid_.density;
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2;
    Face& face = faces_[static_cast<std::size_t>(f)];
    face.here = f % 2 == 0 ? blk_.owned.lo[a] == 0 : blk_.owned.hi[a] == cells_[a];
    if (periodic_[static_cast<std::size_t>(a)]) continue;
    const BoundaryParams b = fluid_.boundary(f, cfg_);
    face.ramp = b.ramp;
    if (b.type == "symmetry") {
      face.kind = Face::symmetry;
    } else if (b.type == "wall" || b.type == "velocity") {
      face.kind = Face::dirichlet;
      if (b.type == "velocity") face.velocity = {b.value.values[0], b.value.values[1], b.value.values[2]};
      face.wall = face.velocity[a] == 0.0;
      face.profiled = b.profile != "uniform";
      face.boundary = b;
    } else {
      face.kind = Face::open;
      face.convective = b.type == "outflow";
      has_open_ = true;
      if (b.type == "pressure") face.pressure = b.value.values[0];
    }
  }
  boundary_speed_ = fv::boundary_speeds(fluid_, cfg_);
  const std::size_t padded = ex_.field_size(), owned = static_cast<std::size_t>(blk_.owned_cells());
  for (auto* f : {&u_, &u_old_, &ustar_, &adv_, &adv_old_, &source_, &source_old_, &top_})
    for (auto& c : *f) c.assign(padded, 0.0);
  p_field_.assign(padded, 0.0);
  phi_.assign(padded, 0.0);
  phi_old_.assign(padded, 0.0);
  rhs_.assign(owned, 0.0);
  x_.assign(owned, 0.0);
  const std::array<bool, 3> per{periodic_[0], periodic_[1], periodic_[2]};
  make_poisson(s.decomposition, per);
  for (int c = 0; c < dims_; ++c)
    viscous_[static_cast<std::size_t>(c)] = std::make_unique<fv::StructSystem>(
        comm_, blk_.owned, cells_, per, solver_options(p_, fmt::format("viscous solve of u_{}", "xyz"[c])));
  set_poisson();
  // The wall functions' ghosts from the first step on (init_turbulence sets
  // the same flag again).
  log_law_ = fluid_.turbulence.on && fluid_.turbulence.wall == "log-law";
  initialise();
  init_turbulence();
}

// The pressure Poisson's solver (fluid.fv.multigrid), named in the log.
void FvSolver::make_poisson(const coupler::Decomposition& dec, const std::array<bool, 3>& per) {
  const std::array<double, 3> h{h_[0], h_[1], h_[2]};
  if (p_.multigrid == "geometric" && fv::PoissonMultigrid::suits(dec, h)) {
    std::array<bool, 6> open{};
    for (std::size_t f = 0; f < 6; ++f) open[f] = faces_[f].kind == Face::open;
    const fv::PoissonMultigrid::Options opt{p_.tolerance, p_.max_iterations, 3, "pressure Poisson solve"};
    poisson_mg_ = std::make_unique<fv::PoissonMultigrid>(dec, rank_, comm_, h, open, opt);
    if (rank_ == 0)
      log::info("fv: the pressure Poisson by conjugate gradients and the geometric multigrid ({} levels, the "
                "coarsest by hypre's PFMG)",
                poisson_mg_->levels());
    return;
  }
  poisson_ = std::make_unique<fv::StructSystem>(comm_, blk_.owned, cells_, per,
                                                solver_options(p_, "pressure Poisson solve"));
  if (rank_ == 0)
    log::info("fv: the pressure Poisson by hypre's conjugate gradients and {}{}",
              p_.multigrid == "smg" ? "SMG" : "PFMG",
              p_.multigrid == "geometric" ? " (the geometric multigrid needs every rank's block to halve along "
                                            "each axis and cells of aspect ratio at most 2)"
                                          : "");
}

// Where the time went, for the log: the share of the pressure Poisson and
// viscous solves in the steps (bench-fv reports the same).
FvSolver::~FvSolver() {
  if (rank_ != 0 || steps_ == 0 || step_seconds_ <= 0) return;
  log::info("fv: {} steps in {:.3f} s: pressure Poisson {:.1f} %, viscous solves {:.1f} %, the rest {:.1f} %",
            steps_, step_seconds_, 100 * poisson_seconds_ / step_seconds_,
            100 * viscous_seconds_ / step_seconds_,
            100 * (step_seconds_ - poisson_seconds_ - viscous_seconds_) / step_seconds_);
  if (turbulent_)
    log::info("fv: k-epsilon {:.1f} % of the steps (its k and epsilon solves {:.1f} %)",
              100 * turbulence_seconds_ / step_seconds_, 100 * scalar_solve_seconds_ / step_seconds_);
  if (ibm_)
    log::info("fv: immersed boundary {:.1f} % of the steps ({:.3f} s: stencils, forcing iterations, their "
              "reductions)",
              100 * ibm_seconds_ / step_seconds_, ibm_seconds_);
}

// The initial state (fluid.initial) sampled at the faces and centres; the
// boundary faces take their values; the initial field is not projected (a
// divergence-free one stays so; the first step projects any other).
void FvSolver::initialise() {
  const auto& d = cfg_.domain;
  for_padded([&](const long* at, long n) {
    for (int c = 0; c < dims_; ++c) {
      Vec3 x, u;
      double p;
      for (int a = 0; a < 3; ++a)
        x[a] = d.lower[a] + (blk_.owned.lo[a] + at[a] + (a == c ? 0.0 : 0.5)) * h_[a];
      fluid_.initial_state(cfg_, x, u, p);
      u_[static_cast<std::size_t>(c)][n] = u[c];
    }
    Vec3 x, u;
    double p;
    for (int a = 0; a < 3; ++a) x[a] = d.lower[a] + (blk_.owned.lo[a] + at[a] + 0.5) * h_[a];
    fluid_.initial_state(cfg_, x, u, p);
    p_field_[n] = p;
  });
  for (int c = 0; c < dims_; ++c) {
    const auto C = static_cast<std::size_t>(c);
    const long n_c = blk_.extent[c];
    for_owned([&](const long* at, long n, long) {
      if (at[c] == n_c - 1) top_[C][n] = u_[C][n + stride(c)];
    });
  }
  fill_ghosts(u_, 0.0);
  fill_pressure_ghosts(p_field_, 0.0, false, 0.0);
}

void FvSolver::set_owned(Field& f, const std::vector<double>& v) const {
  for_owned(
      [&](const long*, long n, long o) { f[static_cast<std::size_t>(n)] = v[static_cast<std::size_t>(o)]; });
}

std::vector<double> FvSolver::owned_of(const Field& f) const {
  std::vector<double> v(static_cast<std::size_t>(blk_.owned_cells()));
  for_owned(
      [&](const long*, long n, long o) { v[static_cast<std::size_t>(o)] = f[static_cast<std::size_t>(n)]; });
  return v;
}

// The largest |u_c| on this rank's faces, boundary faces included, reduced.
double FvSolver::stable_step() {
  double umax[4] = {0, 0, 0, 0};  // and 1 where a value is not finite
  for (int c = 0; c < dims_; ++c) {
    const double* __restrict q = u_[static_cast<std::size_t>(c)].data();
    const long sc = stride(c);
    // By rows, the row's largest |u| and a sum of 0 x u (NaN where any value
    // is not finite) in locals, so that the loop vectorises.
    double m = 0.0, nan = 0.0;
    for_owned_rows([&](const long*, long n0, long, long len) {
      for (long n = n0; n < n0 + len; ++n) {
        const double a = std::abs(q[n]), b = std::abs(q[n + sc]);
        nan += 0.0 * a + 0.0 * b;
        m = a > m ? a : m;
        m = b > m ? b : m;
      }
    });
    umax[c] = m;
    if (nan != 0.0) umax[3] = 1;
  }
  MPI_Allreduce(MPI_IN_PLACE, umax, 4, MPI_DOUBLE, MPI_MAX, comm_);
  if (umax[3] > 0)
    throw std::runtime_error(
        fmt::format("fv: the velocity is not finite at t = {:.6g} s (step {}); lower "
                    "fluid.fv.cfl or fluid.fv.max_step",
                    time_, steps_));
  velocity_scale_ = std::max({umax[0], umax[1], umax[2]});
  if (first_window_)
    fv::raise_to(umax, boundary_speed_, marker_speed_);  // a lid, an inlet, a body at the start
  double limit = fv::cfl_step(p_.cfl, umax, h_, dims_);
  if (p_.max_step > 0) limit = std::min(limit, p_.max_step);
  return limit;
}

void FvSolver::step(double dt) {
  const double start = MPI_Wtime();
  const double omega = dt_prev_ > 0 ? dt / dt_prev_ : 1.0;
  const fv::Imex s = steps_ == 0          ? fv::Imex::first()
                     : p_.time == "cnab2" ? fv::Imex::cnab2(omega)
                                          : fv::Imex::sbdf2(omega);
  momentum(s, dt);
  if (!ibm_in_predictor_) force_immersed(s, dt);
  project(s, dt, steps_ > 0);
  std::swap(u_old_, u_);
  std::swap(u_, ustar_);
  std::swap(adv_old_, adv_);
  if (turbulent_) turbulence_step(dt);
  if (source_fresh_) {  // the last step's source: a copy only when set_source gave a new one
    source_old_ = source_;
    source_fresh_ = false;
  }
  dt_prev2_ = dt_prev_;
  dt_prev_ = dt;
  time_ = next_time_;
  ++steps_;
  ++window_steps_;
  last_dt_ = dt;
  step_seconds_ += MPI_Wtime() - start;
}

// The window in equal steps: planned at its start (the CFL step, at most twice
// the last, the window split evenly) and planned again for the rest only when
// the flow outgrows the step. Equal steps keep the implicit matrices (they
// depend on dt) and their multigrid hierarchies from one step to the next.
void FvSolver::advance(double window) {
  first_window_ = steps_ == 0;
  marker_speed_ = markers_speed_.over(window);
  window_steps_ = 0;
  poisson_iterations_ = viscous_iterations_ = 0;
  fv::step_window(time_, dt_prev_, window, [this] { return stable_step(); }, [this](double dt, double t) {
    next_time_ = t;
    step(dt);
  });
  max_divergence_ = max_divergence(u_);
}

}  // namespace coflow::fluid
