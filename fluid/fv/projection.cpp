// fv: the projection (Chorin 1968, incremental pressure correction): the
// pressure increment phi solves -lap(phi) = -(rho a0 / dt) div(u*) with zero
// normal gradient at walls and velocity faces and the face's pressure change
// at open faces; u = u* - dt / (rho a0) grad(phi), p += phi. The first step
// has no pressure to increment: its momentum step leaves the pressure out and
// phi is the pressure itself (the open faces' values on them), so that the
// initial pressure need not match the faces.
#include <cmath>

#include "fluid/fv/fv_solver.hpp"

namespace coflow::fluid {

double FvSolver::divergence_at(const Faces& u, long n) const {
  double div = 0.0;
  for (int c = 0; c < dims_; ++c) {
    const auto& q = u[static_cast<std::size_t>(c)];
    div += (q[n + stride(c)] - q[n]) / h_[c];
  }
  return div;
}

void FvSolver::set_poisson() {
  if (!poisson_) return;  // the geometric multigrid builds its own operator
  fv::StructSystem::Rows m(static_cast<std::size_t>(blk_.owned_cells()));
  for_owned([&](const long* at, long, long o) {
    const auto O = static_cast<std::size_t>(o);
    for (int d = 0; d < dims_; ++d) {
      const double k = 1.0 / (h_[d] * h_[d]);
      for (int side = 0; side < 2; ++side) {
        auto& coupling =
            side == 0 ? m.lower[static_cast<std::size_t>(d)] : m.upper[static_cast<std::size_t>(d)];
        const long g = blk_.owned.lo[d] + at[d];
        const bool beyond = !periodic_[d] && (side == 0 ? g == 0 : g + 1 == cells_[d]);
        if (!beyond) {
          m.diag[O] += k;
          coupling[O] -= k;
        } else if (faces_[static_cast<std::size_t>(2 * d + side)].kind == Face::open) {
          m.diag[O] += 2 * k;  // ghost 2 dp_b - phi
        }
      }
    }
  });
  poisson_->set(m);
}

// The weights of the last two pressure increments in the Poisson solve's
// first guess, guess = w[0] phi + w[1] phi_old: the last increment alone up to
// the third step (the first step's phi is the pressure itself), then the
// increment extrapolated linearly in time from the last two, as rates phi / dt
// at the steps' midpoints (with equal steps 2 phi_n - phi_n-1). The relative
// tolerance is on the residual against the right-hand side, so a closer guess
// saves iterations (bench-fv's cavity: 9.5 at 128^2, 10.1 at 512^2 and 14.2 at
// 128^3, against 11.0, 11.2 and 15.0 with the last increment, from another
// machine's run; docs/performance.md).
std::array<double, 2> FvSolver::guess_weights(double dt) const {
  if (steps_ < 3) return {1.0, 0.0};
  const double s = (dt + dt_prev_) / (dt_prev_ + dt_prev2_);
  return {dt * (1.0 + s) / dt_prev_, -dt * s / dt_prev2_};
}

// The right-hand side of the Poisson rows, with the open faces' pressure
// change from t0 to t1.
void FvSolver::poisson_rhs(double factor, double t0, double t1, bool incremental) {
  double sum = 0.0;
  const auto w = guess_weights(t1 - t0);
  for_owned([&](const long* at, long n, long o) {
    double r = -factor * divergence_at(ustar_, n);
    for (int d = 0; d < dims_; ++d)
      for (int side = 0; side < 2; ++side) {
        const Face& f = faces_[static_cast<std::size_t>(2 * d + side)];
        const long g = blk_.owned.lo[d] + at[d];
        if (f.kind == Face::open && (side == 0 ? g == 0 : g + 1 == cells_[d]))
          r += 2 * (f.pressure_at(t1) - (incremental ? f.pressure_at(t0) : 0.0)) / (h_[d] * h_[d]);
      }
    rhs_[static_cast<std::size_t>(o)] = r;
    x_[static_cast<std::size_t>(o)] = incremental ? w[0] * phi_[n] + w[1] * phi_old_[n] : p_field_[n];
    sum += r;
  });
  if (has_open_) return;
  // Walls all round (or periodic): phi is fixed up to a constant, and the
  // right-hand side must sum to zero; take out its round-off.
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, comm_);
  const double cells = static_cast<double>(cells_[0] * cells_[1] * cells_[2]);
  double hmin = h_[0];
  for (int d = 1; d < dims_; ++d) hmin = std::min(hmin, h_[d]);
  fv::check_closed_balance(sum, cells, factor, velocity_scale_, hmin);
  const double mean = sum / cells;
  for (auto& r : rhs_) r -= mean;
}

void FvSolver::project(const fv::Imex& s, double dt, bool incremental) {
  const double t0 = time_, t1 = next_time_, factor = rho_ * s.a0 / dt;
  extrapolate_open_faces(ustar_, dt);
  fill_ghosts(ustar_, t1);
  poisson_rhs(factor, t0, t1, incremental);
  // The residual need not fall below a divergence of 1e-6 tolerance U / h per
  // cell (U the largest velocity): a flow already without divergence (a
  // fully developed one) gives a right-hand side of round-off size.
  double hmin = h_[0];
  for (int d = 1; d < dims_; ++d) hmin = std::min(hmin, h_[d]);
  const double cells = static_cast<double>(cells_[0] * cells_[1] * cells_[2]);
  const double floor = 1e-6 * p_.tolerance * factor * velocity_scale_ / hmin * std::sqrt(cells);
  const double start = MPI_Wtime();
  int iterations = 0;
  if (poisson_mg_) {
    poisson_mg_->set_absolute_floor(floor);
    poisson_mg_->solve(rhs_, x_);
    iterations = poisson_mg_->last_iterations();
  } else {
    poisson_->set_absolute_floor(floor);
    poisson_->solve(rhs_, x_);
    iterations = poisson_->last_iterations();
  }
  poisson_seconds_ += MPI_Wtime() - start;
  ++poisson_solves_;
  poisson_iteration_sum_ += iterations;
  poisson_iterations_ = std::max(poisson_iterations_, iterations);
  if (!has_open_) {  // the constant of phi: mean zero
    double sum = 0.0;
    for (double v : x_) sum += v;
    MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, comm_);
    const double mean = sum / static_cast<double>(cells_[0] * cells_[1] * cells_[2]);
    for (auto& v : x_) v -= mean;
  }
  std::swap(phi_old_, phi_);
  set_owned(phi_, x_);
  if (incremental)
    fill_pressure_ghosts(phi_, t1, true, t0);
  else
    fill_pressure_ghosts(phi_, t1, false, t1);
  for (int c = 0; c < dims_; ++c) {
    const auto C = static_cast<std::size_t>(c);
    const long sc = stride(c), n_c = blk_.extent[c];
    for_owned([&](const long* at, long n, long) {
      if (!is_dirichlet_face(c, at[c])) ustar_[C][n] -= (phi_[n] - phi_[n - sc]) / (factor * h_[c]);
      const bool top = at[c] == n_c - 1 && faces_[2 * C + 1].here && faces_[2 * C + 1].kind == Face::open;
      if (top) top_[C][n] -= (phi_[n + sc] - phi_[n]) / (factor * h_[c]);
    });
  }
  for_owned([&](const long*, long n, long) { p_field_[n] = incremental ? p_field_[n] + phi_[n] : phi_[n]; });
  fill_pressure_ghosts(p_field_, t1, false, t1);
  fill_ghosts(ustar_, t1);
}

double FvSolver::max_divergence(const Faces& u) const {
  double worst = 0.0;
  for_owned([&](const long*, long n, long) { worst = std::max(worst, std::abs(divergence_at(u, n))); });
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return worst;
}

}  // namespace coflow::fluid
