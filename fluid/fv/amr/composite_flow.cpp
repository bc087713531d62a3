#include "fluid/fv/amr/composite_flow.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "coflow/output.hpp"
#include "fluid/fv/amr/composite_laplacian.hpp"
#include "fluid/fv/amr/refinement_criteria.hpp"
#include "fluid/fv/scheme.hpp"

namespace coflow::fluid::fv::amr {
CompositeFlow::CompositeFlow(Forest& forest, const GridGeometry& geometry, double viscosity,
                             IjSystem::Options solve)
    : forest_(forest),
      geometry_(geometry),
      nu_(viscosity),
      dims_(forest.spec().dims),
      nc_(forest.spec().components),
      solve_(solve) {
  if (nc_ < dims_ + 1)
    throw std::invalid_argument("refinement: the flow keeps at least dims + 1 values per cell");
  build();
}

void CompositeFlow::build() {
  grid_ = std::make_unique<CompositeGrid>(forest_, geometry_);
  faces_ = build_faces(*grid_);
  // dp/dn = 0 on walls and inlets, p = 0 on outlets.
  std::array<FaceCondition, 6> conditions;
  bool any_outlet = false;
  for (std::size_t k = 0; k < 6; ++k) {
    const bool open = kinds_[k] == Boundary::outlet && !forest_.spec().periodic[k / 2];
    conditions[k] = open ? FaceCondition::dirichlet : FaceCondition::neumann;
    any_outlet = any_outlet || open;
  }
  auto L = assemble_laplacian(*grid_, faces_, conditions);
  // Then the faces read fields gathered with their ghosts: ids to slots.
  h_.resize(faces_.size());
  for (std::size_t c = 0; c < faces_.size(); ++c) {
    h_[c] = grid_->spacing(grid_->local_cell(static_cast<long>(c)).level);
    for (auto& f : faces_[c]) {
      f.gradient = grid_->to_slots(f.gradient);
      f.value = grid_->to_slots(f.value);
      if (f.across >= 0) f.across_slot = grid_->slot(f.across);
    }
  }
  flatten_faces();
  mac_.assign(flat_.size(), 0.0);
  // Without an outlet constants are the kernel; pin global cell 0 to zero.
  // Its divergence is then zero too, as the divergences sum to zero.
  pinned_ = !any_outlet;
  if (pinned_ && grid_->first_cell() == 0 && !L.rows.empty()) L.rows[0] = {{0, 1.0}};
  poisson_.reset();
  poisson_ = std::make_unique<IjSystem>(forest_.comm(), grid_->first_cell(), L.rows, solve_);
  viscous_.clear();  // the implicit diffusion's operators: again at the next step
  global_faces_.clear();
  source_.clear();
  for (auto& p : phi_) p.clear();
  for (auto& r : phi_rate_) r.clear();
}

void CompositeFlow::flatten_faces() {
  face_begin_.assign(1, 0);
  flat_.clear();
  stencil_slot_.clear();
  stencil_weight_.clear();
  auto append = [&](const Stencil& st) {
    for (const auto& [slot, w] : st) {
      stencil_slot_.push_back(static_cast<std::size_t>(slot));
      stencil_weight_.push_back(w);
    }
    if (stencil_slot_.size() > std::numeric_limits<std::uint32_t>::max())
      throw std::runtime_error("refinement: more than 2^32 stencil entries on one rank; run on more ranks");
    return static_cast<std::uint32_t>(stencil_slot_.size());
  };
  for (auto& cell : faces_) {
    for (auto& f : cell) {
      FlatFace ff{f.axis, f.side, f.fraction, f.wall, 0, 0, 0};
      ff.value_begin = static_cast<std::uint32_t>(stencil_slot_.size());
      ff.value_end = append(f.value);
      ff.gradient_end = append(f.gradient);
      flat_.push_back(ff);
      f.value = Stencil{};  // held once: the flat copy is what the operators read
      f.gradient = Stencil{};
    }
    face_begin_.push_back(flat_.size());
  }
}

void CompositeFlow::set_inlet(int face, Inflow inflow) {
  kinds_[static_cast<std::size_t>(face)] = Boundary::inlet;
  viscous_.clear();
  inflow_[static_cast<std::size_t>(face)] = std::move(inflow);
}

void CompositeFlow::set_symmetry(int face) {
  kinds_[static_cast<std::size_t>(face)] = Boundary::symmetry;
  viscous_.clear();
}

void CompositeFlow::set_outlet(int face) {
  kinds_[static_cast<std::size_t>(face)] = Boundary::outlet;
  build();  // the pressure's condition changes
}

std::array<double, 3> CompositeFlow::imposed(const SubFace& f, std::size_t c, const Field& g) const {
  const std::size_t k = face_of(f);
  if (kinds_[k] == Boundary::symmetry) {  // no flow through, no shear: the cell's own tangential velocity
    std::array<double, 3> v{0.0, 0.0, 0.0};
    for (std::size_t q = 0; q < g.size(); ++q) v[q] = g[q][c];
    v[static_cast<std::size_t>(f.axis)] = 0.0;
    return v;
  }
  const Inflow& given = kinds_[k] == Boundary::inlet ? inflow_[k] : walls_[k];
  if (!given) return {0.0, 0.0, 0.0};  // a wall at rest
  const auto cell = grid_->local_cell(static_cast<long>(c));
  auto x = grid_->centre(cell);
  x[static_cast<std::size_t>(f.axis)] += 0.5 * f.side * grid_->spacing(cell.level);
  return given(x);
}

bool CompositeFlow::regrid(std::vector<int> marks) {
  keep_coarsening_balanced(*grid_, marks);
  if (!forest_.adapt(marks)) {  // no leaf refined or coarsened: operators and face velocities stand
    grid_ = std::make_unique<CompositeGrid>(forest_, geometry_);  // the leaf lists were rebuilt
    return false;
  }
  build();
  project_initial();
  return true;
}

std::vector<CompositeFlow::Gradient> CompositeFlow::gradients(const Field& g) const {
  std::vector<Gradient> out(faces_.size(), Gradient{});
  for (std::size_t c = 0; c < faces_.size(); ++c) {
    auto& grad = out[c];  // d u_q / d x_axis
    const double h = h_[c];
    for (std::size_t k = face_begin_[c]; k < face_begin_[c + 1]; ++k) {
      const FlatFace& f = flat_[k];
      for (std::size_t q = 0; q < g.size(); ++q) {
        const double face =
            f.wall ? wall_velocity(faces_[c][k - face_begin_[c]], c, g, q) : flat_value(f, g[q]);
        grad[q][static_cast<std::size_t>(f.axis)] += f.fraction * f.side * face / h;
      }
    }
  }
  return out;
}

std::vector<CompositeFlow::Gradient> CompositeFlow::velocity_gradients() {
  return gradients(with_ghosts(read_velocity()));
}

void CompositeFlow::vorticity(int component) {
  const auto all = velocity_gradients();
  const auto per = static_cast<std::size_t>(grid_->cells_per_patch()), nc = static_cast<std::size_t>(nc_);
  for (std::size_t c = 0; c < faces_.size(); ++c) {
    const auto& grad = all[c];
    const double wz = grad[1][0] - grad[0][1];
    double w2 = wz * wz;
    if (dims_ == 3) w2 += std::pow(grad[2][1] - grad[1][2], 2) + std::pow(grad[0][2] - grad[2][0], 2);
    forest_.data(c / per)[(c % per) * nc + static_cast<std::size_t>(component)] = std::sqrt(w2);
  }
}

CompositeFlow::~CompositeFlow() = default;

double CompositeFlow::volume(long c) const {
  return std::pow(h_[static_cast<std::size_t>(c)], dims_);
}

CompositeFlow::Field CompositeFlow::read_velocity() const {
  const auto nc = static_cast<std::size_t>(nc_), per = static_cast<std::size_t>(grid_->cells_per_patch());
  Field u(static_cast<std::size_t>(dims_),
          std::vector<double>(static_cast<std::size_t>(grid_->local_cells())));
  for (std::size_t l = 0; l < forest_.leaves().size(); ++l)
    for (std::size_t c = 0; c < per; ++c)
      for (std::size_t q = 0; q < u.size(); ++q) u[q][l * per + c] = forest_.data(l)[c * nc + q];
  return u;
}

void CompositeFlow::write(const Field& u) {
  const auto nc = static_cast<std::size_t>(nc_), per = static_cast<std::size_t>(grid_->cells_per_patch());
  for (std::size_t l = 0; l < forest_.leaves().size(); ++l)
    for (std::size_t c = 0; c < per; ++c)
      for (std::size_t q = 0; q < u.size(); ++q) forest_.data(l)[c * nc + q] = u[q][l * per + c];
}

CompositeFlow::Field CompositeFlow::with_ghosts(const Field& u) {
  write(u);
  forest_.exchange_ghosts();
  Field g(u.size());
  for (std::size_t q = 0; q < u.size(); ++q) grid_->gather(static_cast<int>(q), g[q]);
  return g;
}

double CompositeFlow::wall_velocity(const SubFace& f, std::size_t c, const Field& g, std::size_t q) const {
  return outlet(f) ? g[q][c] : imposed(f, c, g)[q];  // an outlet carries the cell's value
}

std::vector<double> CompositeFlow::pressure() const {
  const auto nc = static_cast<std::size_t>(nc_), per = static_cast<std::size_t>(grid_->cells_per_patch());
  std::vector<double> p;
  p.reserve(h_.size());
  for (std::size_t l = 0; l < forest_.leaves().size(); ++l)
    for (std::size_t c = 0; c < per; ++c)
      p.push_back(forest_.data(l)[c * nc + static_cast<std::size_t>(dims_)]);
  return p;
}

void CompositeFlow::set_pressure(const std::vector<double>& p) {
  const auto nc = static_cast<std::size_t>(nc_), per = static_cast<std::size_t>(grid_->cells_per_patch());
  for (std::size_t l = 0, k = 0; l < forest_.leaves().size(); ++l)
    for (std::size_t c = 0; c < per; ++c) forest_.data(l)[c * nc + static_cast<std::size_t>(dims_)] = p[k++];
}

// The explicit rates: advection through the faces, the viscous stress
// (molecular and eddy; in *viscous where the diffusion is implicit, and not
// computed with `none`), the stress's transposed part (always here: it is
// explicit in either step) and the source.
CompositeFlow::Field CompositeFlow::rates(const Field& u, Viscous part, Field* viscous) {
  const Field g = with_ghosts(u);
  Field r(u.size(), std::vector<double>(u[0].size(), 0.0));
  if (part == Viscous::apart) *viscous = r;
  std::vector<double> nut;
  if (eddy_ >= 0) grid_->gather(eddy_, nut);
  const Field transpose = eddy_ >= 0 ? stress_transpose(g, nut) : Field{};
  const std::size_t nq = u.size();
  const bool viscous_part = part != Viscous::none;
  for (std::size_t c = 0; c < faces_.size(); ++c) {
    const double h = h_[c];
    // Each face once for every component (each component's sums in the
    // faces' order, as one component at a time would take them).
    double carried[3] = {0.0, 0.0, 0.0}, stress[3] = {0.0, 0.0, 0.0}, eddy[3] = {0.0, 0.0, 0.0};
    for (std::size_t s = 0; s < faces_[c].size(); ++s) {
      const FlatFace& ff = flat_[face_begin_[c] + s];
      if (!ff.wall) {                                 // the interior faces, most of them: flat stencils
        const double outward = ff.side * mac_[face_begin_[c] + s];  // normal velocity out of the cell
        const double nut_face = viscous_part && eddy_ >= 0 ? std::max(0.0, flat_value(ff, nut)) : 0.0;
        for (std::size_t q = 0; q < nq; ++q) {
          if (viscous_part) {
            const double du = flat_gradient(ff, g[q]);
            stress[q] += ff.fraction * nu_ * du;
            if (eddy_ >= 0) eddy[q] += ff.fraction * nut_face * du;
          }
          carried[q] -= ff.fraction * outward * flat_value(ff, g[q]);
        }
        continue;
      }
      const auto& f = faces_[c][s];
      if (outlet(f)) {  // carried out at the cell's value; no viscous stress
        for (std::size_t q = 0; q < nq; ++q)
          carried[q] -= f.fraction * f.side * mac_[face_begin_[c] + s] * g[q][c];
        continue;
      }
      // The imposed velocity half a cell away; carried in or out with it.
      const auto ub = imposed(f, c, g);
      const double nut_wall = viscous_part && eddy_ >= 0 ? boundary_eddy(f, c, nut) : 0.0;
      for (std::size_t q = 0; q < nq; ++q) {
        if (viscous_part) stress[q] += f.fraction * nu_ * 2.0 * (ub[q] - g[q][c]) / h;
        if (viscous_part && eddy_ >= 0) eddy[q] += f.fraction * nut_wall * 2.0 * (ub[q] - g[q][c]) / h;
        carried[q] -= f.fraction * f.side * ub[static_cast<std::size_t>(f.axis)] * ub[q];
      }
    }
    for (std::size_t q = 0; q < nq; ++q) {
      double source = source_.empty() ? 0.0 : source_[q][c];
      if (!transpose.empty()) source += transpose[q][c];
      if (part == Viscous::apart) {  // the eddy stress implicit too (solve_viscous)
        r[q][c] = carried[q] / h + source;
        (*viscous)[q][c] = (stress[q] + eddy[q]) / h;
      } else {
        r[q][c] = (stress[q] + eddy[q] + carried[q]) / h + source;
      }
    }
  }
  return r;
}

// d/dx_d (nu_t d u_d / dx_c) = (d nu_t / dx_d)(d u_d / dx_c) where div u = 0:
// both gradients by Gauss's theorem over the cell's faces, nu_t's face values
// from the value stencils (on the domain's faces boundary_eddy's).
CompositeFlow::Field CompositeFlow::stress_transpose(const Field& g, const std::vector<double>& nut) const {
  const auto grad = gradients(g);
  Field out(g.size(), std::vector<double>(faces_.size(), 0.0));
  for (std::size_t c = 0; c < faces_.size(); ++c) {
    std::array<double, 3> dnut{0.0, 0.0, 0.0};
    for (std::size_t s = 0; s < faces_[c].size(); ++s) {
      const FlatFace& f = flat_[face_begin_[c] + s];
      const double face = !f.wall ? std::max(0.0, flat_value(f, nut)) : boundary_eddy(faces_[c][s], c, nut);
      dnut[static_cast<std::size_t>(f.axis)] += f.fraction * f.side * face / h_[c];
    }
    for (std::size_t q = 0; q < g.size(); ++q)
      for (std::size_t d = 0; d < g.size(); ++d) out[q][c] += dnut[d] * grad[c][d][q];
  }
  return out;
}

void CompositeFlow::project(Field& u, double dt, int stage) {
  const Field g = with_ghosts(u);
  const std::size_t n = faces_.size();
  std::vector<double> b(n, 0.0);
  std::vector<double>& phi = phi_[static_cast<std::size_t>(stage)];  // this stage's last pressure
  const bool solved_before = phi.size() == n;
  phi.resize(n, 0.0);
  for (std::size_t c = 0; c < n; ++c) {
    const double h = h_[c];
    double div = 0.0;
    for (std::size_t s = 0; s < faces_[c].size(); ++s) {
      const FlatFace& f = flat_[face_begin_[c] + s];
      const auto axis = static_cast<std::size_t>(f.axis);
      mac_[face_begin_[c] + s] =
          f.wall ? wall_velocity(faces_[c][s], c, g, axis)  // an outlet's is corrected below
                 : flat_value(f, g[axis]);
      div += f.fraction * f.side * mac_[face_begin_[c] + s];
    }
    b[c] = div / (h * dt);
  }
  if (pinned_) check_closed_balance(b, dt);
  if (pinned_ && grid_->first_cell() == 0 && n > 0) b[0] = 0.0;
  solve_pressure(b, phi, dt, stage, solved_before);
  // The pressure into the forest's pressure component, exchanged with the velocity.
  set_pressure(phi);
  forest_.exchange_ghosts();
  std::vector<double> p;
  grid_->gather(dims_, p);
  for (std::size_t c = 0; c < n; ++c) {
    const double h = h_[c];
    for (std::size_t s = 0; s < faces_[c].size(); ++s) {
      const FlatFace& ff = flat_[face_begin_[c] + s];
      // dp/dn outward: p = 0 on an outlet half a cell away, 0 on walls and inlets.
      if (!ff.wall)
        mac_[face_begin_[c] + s] -= dt * ff.side * flat_gradient(ff, p);
      else if (outlet(faces_[c][s]))
        mac_[face_begin_[c] + s] -= dt * ff.side * (-2.0 * p[c] / h);
    }
  }
  subtract_gradient(u, p, dt);
  write(u);
}

// Without an outlet the boundary's velocities must let as much fluid in as
// out: the cells' net fluxes then sum to round-off, which the pinned cell
// takes up. As on fv (fv::check_closed_balance), a mean divergence above
// 1e-12 U / h stops the run instead of being spread into that one cell (b:
// each cell's divergence / (h dt); U the largest face velocity).
void CompositeFlow::check_closed_balance(const std::vector<double>& b, double dt) const {
  double sums[2] = {0.0, 0.0};        // the net flux out, the volume
  double tops[2] = {0.0, -HUGE_VAL};  // the largest |face velocity|, -(the smallest h)
  for (std::size_t c = 0; c < b.size(); ++c) {
    const double h = h_[c], area = dims_ == 3 ? h * h : h;
    sums[0] += b[c] * h * dt * area;
    sums[1] += area * h;
    tops[1] = std::max(tops[1], -h);
  }
  for (const double m : mac_) tops[0] = std::max(tops[0], std::fabs(m));
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, forest_.comm());
  MPI_Allreduce(MPI_IN_PLACE, tops, 2, MPI_DOUBLE, MPI_MAX, forest_.comm());
  if (sums[1] > 0.0) fv::check_closed_balance(-sums[0] / sums[1], 1.0, 1.0, tops[0], -tops[1]);
}

// The Poisson solve of a stage, from the guess phi + dt rate (the stage's
// pressure extrapolated linearly in time from its last two solves, as fv
// extrapolates its increments: 12.3 against 10.4 iterations a solve in
// bench-amr's jet, 9.4 against 7.8 in the adaptive cylinder); the rate then
// from this solve. The initial projection (stage 2) keeps its last pressure.
void CompositeFlow::solve_pressure(const std::vector<double>& b, std::vector<double>& phi, double dt,
                                   int stage, bool solved_before) {
  std::vector<double>* rate =
      stage < 2 && solved_before ? &phi_rate_[static_cast<std::size_t>(stage)] : nullptr;
  // The rate's storage holds the last pressure over the solve (no copy).
  if (rate && rate->size() == phi.size())
    for (std::size_t c = 0; c < phi.size(); ++c) {
      const double last = phi[c];
      phi[c] += dt * (*rate)[c];
      (*rate)[c] = last;
    }
  else if (rate)
    *rate = phi;
  poisson_->solve(b, phi);
  iterations_ = poisson_->last_iterations();
  if (rate)
    for (std::size_t c = 0; c < phi.size(); ++c) (*rate)[c] = (phi[c] - (*rate)[c]) / dt;
}

void CompositeFlow::subtract_gradient(Field& u, const std::vector<double>& p, double dt) const {
  for (std::size_t c = 0; c < faces_.size(); ++c) {
    const double h = h_[c];
    // Gauss's theorem over the cell's faces, in their order, the cell's
    // velocity held in a local array meanwhile and stored once.
    double v[3] = {0.0, 0.0, 0.0};
    for (std::size_t q = 0; q < u.size(); ++q) v[q] = u[q][c];
    for (std::size_t k = face_begin_[c]; k < face_begin_[c + 1]; ++k) {
      const FlatFace& f = flat_[k];
      const double face = !f.wall ? flat_value(f, p) : outlet(faces_[c][k - face_begin_[c]]) ? 0.0 : p[c];
      v[f.axis] -= dt * f.fraction * f.side * face / h;
    }
    for (std::size_t q = 0; q < u.size(); ++q) u[q][c] = v[q];
  }
}

void CompositeFlow::project_initial() {
  // A pure projection: its potential is not the flow's pressure, which the
  // forest keeps.
  const auto kept = pressure();
  Field u = read_velocity();
  project(u, 1.0, 2);
  set_pressure(kept);
}

void CompositeFlow::step(double dt) {
  if (implicit_) {
    step_implicit(dt);
    return;
  }
  const Field u0 = read_velocity();
  const Field r0 = rates(u0);
  Field u1 = u0;
  for (std::size_t q = 0; q < u1.size(); ++q)
    for (std::size_t c = 0; c < u1[q].size(); ++c) u1[q][c] += dt * r0[q][c];
  if (forcing_) forcing_(u1, dt, 0);
  project(u1, dt, 0);
  const Field r1 = rates(u1);
  Field u2 = u0;
  for (std::size_t q = 0; q < u2.size(); ++q)
    for (std::size_t c = 0; c < u2[q].size(); ++c) u2[q][c] = 0.5 * (u0[q][c] + u1[q][c] + dt * r1[q][c]);
  if (forcing_) forcing_(u2, dt, 1);
  project(u2, dt, 1);
  // u2 = u0 + dt (r0 + r1) / 2 - dt grad(phi_1 / 2 + phi_2): the step's
  // pressure is phi_1 / 2 + phi_2 (each stage's solution kept in phi_).
  std::vector<double> p(phi_[1].size());
  for (std::size_t k = 0; k < p.size(); ++k) p[k] = 0.5 * phi_[0][k] + phi_[1][k];
  set_pressure(p);
}

// Heun's step with the diffusion D implicit (A: advection and source), in
// incremental pressure-correction form (G: the cells' pressure gradient,
// p the last step's pressure): predictor (1 - dt D) u1* = u0 + dt (A(u0) -
// G p), forced (by f1) and projected to u1 = u1* + f1 - dt G phi_1;
// corrector (1 - dt D / 2) u2* = u0 + dt (A(u0) + A(u1) + D u0) / 2 + f1
// - dt G (p + phi_1), forced and projected by phi_2; the step's pressure is
// p + phi_1 + phi_2. The corrector takes the predictor's forcing in full,
// as its pressure (stage_weight()). Formally second order in time: the
// trapezoidal rule for D, Heun's for A (on a fixed grid the approximate
// projection's error per step stays: docs/validation.md). Without the old
// pressure in the predictor, the no-slip condition of the implicit solve
// would act on its gradient: the steady state would move with dt. With an
// immersed boundary's forcing the old pressure is left out (p = 0 above):
// the forcing and the pressure carried from step to step fed each other, and
// the cylinder at Re 20 blew up at steps of CFL 0.25 (docs/validation.md).
void CompositeFlow::step_implicit(double dt) {
  if (eddy_ >= 0) viscous_.clear();  // nu_t changed: its operators again, held over the step
  const Field u0 = read_velocity();
  Field d0;
  const Field a0 = rates(u0, Viscous::apart, &d0);
  // rates() exchanged the forest's ghosts, the last step's pressure with them.
  const bool incremental = !forcing_;
  std::vector<double> p0 = pressure();
  if (!incremental) std::fill(p0.begin(), p0.end(), 0.0);
  std::vector<double> p0_slots;
  if (incremental) grid_->gather(dims_, p0_slots);
  Field b = u0, predicted = u0;
  for (std::size_t q = 0; q < b.size(); ++q)
    for (std::size_t c = 0; c < b[q].size(); ++c) b[q][c] += dt * a0[q][c];
  if (incremental) subtract_gradient(b, p0_slots, dt);
  solve_viscous(b, predicted, dt, 0);
  Field forced = predicted;
  if (forcing_) forcing_(forced, dt, 0);
  Field u1 = forced;
  project(u1, dt, 0);  // u1 = forced - dt G phi_1
  const Field a1 = rates(u1, Viscous::none);
  for (std::size_t q = 0; q < b.size(); ++q)
    for (std::size_t c = 0; c < b[q].size(); ++c)
      b[q][c] = u0[q][c] + 0.5 * dt * (a0[q][c] + a1[q][c] + d0[q][c]) + (u1[q][c] - predicted[q][c]);
  if (incremental) subtract_gradient(b, p0_slots, dt);
  Field u2 = u1;
  solve_viscous(b, u2, 0.5 * dt, 1);
  if (forcing_) forcing_(u2, dt, 1);
  project(u2, dt, 1);
  std::vector<double> p(p0.size());
  for (std::size_t k = 0; k < p.size(); ++k) p[k] = p0[k] + phi_[0][k] + phi_[1][k];
  set_pressure(p);
}

// Per local cell and sub-face, nu + nu_t at the face (nu_t's value stencil,
// never below 0; on the domain's faces boundary_eddy's).
std::vector<std::vector<double>> CompositeFlow::face_viscosity() const {
  std::vector<double> nut;
  grid_->gather(eddy_, nut);  // the ghosts as the last exchange left them (nu_t holds over the step)
  std::vector<std::vector<double>> out(faces_.size());
  for (std::size_t c = 0; c < faces_.size(); ++c)
    for (std::size_t s = 0; s < faces_[c].size(); ++s) {
      const FlatFace& f = flat_[face_begin_[c] + s];
      out[c].push_back(nu_ +
                       (f.wall ? boundary_eddy(faces_[c][s], c, nut) : std::max(0.0, flat_value(f, nut))));
    }
  return out;
}

void CompositeFlow::solve_viscous(Field& b, Field& x, double theta_dt, std::size_t which) {
  if (viscous_.empty()) {  // each component's conditions: walls and inlets give its value, outlets none
    std::vector<std::vector<double>> a;
    if (eddy_ >= 0) {
      a = face_viscosity();
      if (global_faces_.empty()) global_faces_ = build_faces(*grid_);
    }
    for (std::size_t q = 0; q < static_cast<std::size_t>(dims_); ++q) {
      std::array<FaceCondition, 6> conditions;
      for (std::size_t k = 0; k < 6; ++k) {
        const bool given = kinds_[k] == Boundary::wall || kinds_[k] == Boundary::inlet ||
                           (kinds_[k] == Boundary::symmetry && k / 2 == q);
        conditions[k] = given ? FaceCondition::dirichlet : FaceCondition::neumann;
      }
      viscous_.push_back(eddy_ >= 0 ? assemble_laplacian(*grid_, global_faces_, conditions, &a)
                                    : assemble_laplacian(*grid_, conditions));
    }
    for (auto& pair : helmholtz_)
      for (auto& sys : pair) sys.reset();
  }
  for (std::size_t q = 0; q < static_cast<std::size_t>(dims_); ++q) {
    const auto& L = viscous_[q];
    const double scale = eddy_ >= 0 ? theta_dt : theta_dt * nu_;  // the rows hold nu + nu_t, or 1
    // Predictor and corrector keep a system each, rebuilt when the step changes.
    auto& slot = helmholtz_[q][which];
    auto& slot_dt = helmholtz_dt_[q][which];
    if (!slot || slot_dt != theta_dt) {
      std::vector<Stencil> rows = L.rows;
      for (std::size_t c = 0; c < rows.size(); ++c) {
        for (auto& e : rows[c]) e.second *= -scale;
        const long self = grid_->first_cell() + static_cast<long>(c);
        auto at =
            std::find_if(rows[c].begin(), rows[c].end(), [&](const auto& e) { return e.first == self; });
        if (at == rows[c].end()) at = rows[c].insert(rows[c].end(), {self, 0.0});
        at->second += 1.0;
      }
      slot.reset();
      // The velocity itself is solved for (the Poisson gives a potential whose
      // gradient times dt enters): a residual at the Poisson's tolerance would
      // add its round-off step after step, so a hundredth of it (these systems
      // are well conditioned: a few iterations more), above round-off.
      IjSystem::Options tight = solve_;
      tight.tolerance = std::max(1e-13, 0.01 * solve_.tolerance);
      tight.name = "implicit viscous solve (a hundredth of fluid.fv.tolerance)";
      slot = std::make_unique<IjSystem>(forest_.comm(), grid_->first_cell(), rows, tight);
      slot_dt = theta_dt;
    }
    for (const auto& f : L.boundary) {
      const auto k = static_cast<std::size_t>(f.face);
      double g = 0.0;  // outlets and symmetry faces: no gradient, no flow through
      if (kinds_[k] == Boundary::wall && walls_[k]) g = walls_[k](f.point)[q];
      if (kinds_[k] == Boundary::inlet) g = inflow_[k](f.point)[q];
      b[q][static_cast<std::size_t>(f.cell)] += scale * f.coefficient * g;
    }
    slot->solve(b[q], x[q]);
  }
}

namespace {
int sub_faces_per_cell(int dims) {
  return 2 * dims * (1 << (dims - 1));
}  // all faces split
}  // namespace

void CompositeFlow::save(const std::string& dir) {
  forest_.save(dir + "/forest.p4est");
  const auto n = faces_.size(), width = static_cast<std::size_t>(sub_faces_per_cell(dims_));
  // phi: the three pressures, then the two stages' rates (the guesses'
  // history); NaN in every cell for one not known yet on this grid (after a
  // regrid), which load() leaves unknown, as the run that wrote it had it.
  const double unknown = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> mac(n * width, 0.0), phi(n * 5, 0.0);
  for (std::size_t c = 0; c < n; ++c) {
    for (std::size_t s = face_begin_[c]; s < face_begin_[c + 1]; ++s)
      mac[c * width + s - face_begin_[c]] = mac_[s];
    for (std::size_t k = 0; k < 3; ++k) phi[c * 5 + k] = phi_[k].empty() ? unknown : phi_[k][c];
    for (std::size_t k = 0; k < 2; ++k) phi[c * 5 + 3 + k] = phi_rate_[k].empty() ? unknown : phi_rate_[k][c];
  }
  output::write_tables(forest_.comm(), dir + "/flow.h5", 0.0, 0,
                       {{"mac", static_cast<int>(width), n, false, mac, {}}, {"phi", 5, n, false, phi, {}}});
}

void CompositeFlow::load(const std::string& dir) {
  // Rows are global cell ids (write_tables keeps the ranks' order, which is
  // the forest's): any rank count reads its own.
  const auto mac = output::read_dataset(dir + "/flow.h5", "mac");
  const auto phi = output::read_dataset(dir + "/flow.h5", "phi");
  const auto width = static_cast<std::size_t>(sub_faces_per_cell(dims_));
  const auto cells = static_cast<std::size_t>(grid_->global_cells());
  // 5 values a cell (3 pressures, 2 rates); checkpoints written before the
  // rates were kept have 3, every one known (their guesses start again
  // without history).
  const std::size_t per = phi.size() == cells * 5 ? 5 : 3;
  if (mac.size() != cells * width || phi.size() != cells * per)
    throw std::runtime_error("refinement: " + dir + "/flow.h5 does not match its forest");
  // A column of phi is known (finite in every cell) or not (NaN in every cell).
  std::vector<bool> known(per, true);
  for (std::size_t k = 0; k < per && cells > 0; ++k) known[k] = !std::isnan(phi[k]);
  for (const auto* v : {&mac, &phi})
    for (std::size_t i = 0; i < v->size(); ++i) {
      const bool ok = v == &phi && !known[i % per] ? std::isnan((*v)[i]) : std::isfinite((*v)[i]);
      if (!ok)
        throw std::runtime_error(
            fmt::format("refinement: {}/flow.h5 holds a value that is not finite in '{}': the "
                        "checkpoint is damaged; restart from another one",
                        dir, v == &mac ? "mac" : "phi"));
    }
  const auto first = static_cast<std::size_t>(grid_->first_cell());
  for (std::size_t c = 0; c < faces_.size(); ++c)
    for (std::size_t s = 0; s < faces_[c].size(); ++s)
      mac_[face_begin_[c] + s] = mac[(first + c) * width + s];
  for (std::size_t k = 0; k < per; ++k) {
    auto& column = k < 3 ? phi_[k] : phi_rate_[k - 3];
    column.clear();
    if (!known[k]) continue;
    column.resize(faces_.size());
    for (std::size_t c = 0; c < faces_.size(); ++c) column[c] = phi[(first + c) * per + k];
  }
  if (per < 5)
    for (auto& r : phi_rate_) r.clear();
}

std::vector<double> CompositeFlow::divergence() const {
  std::vector<double> div(faces_.size(), 0.0);
  for (std::size_t c = 0; c < faces_.size(); ++c) {
    for (std::size_t s = 0; s < faces_[c].size(); ++s)
      div[c] += faces_[c][s].fraction * faces_[c][s].side * mac_[face_begin_[c] + s];
    div[c] /= h_[c];
  }
  return div;
}

double CompositeFlow::face_divergence() const {
  double worst = 0.0;
  for (const double d : divergence()) worst = std::max(worst, std::isnan(d) ? HUGE_VAL : std::fabs(d));
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, forest_.comm());
  return worst;
}

double CompositeFlow::momentum(int axis) const {
  const Field u = read_velocity();
  double sum = 0.0;
  for (std::size_t c = 0; c < u[0].size(); ++c)
    sum += volume(static_cast<long>(c)) * u[static_cast<std::size_t>(axis)][c];
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, forest_.comm());
  return sum;
}

}  // namespace coflow::fluid::fv::amr
