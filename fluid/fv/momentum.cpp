// fv: the momentum step to the provisional velocity u* (advection explicit,
// diffusion implicit, the pressure of the last step; seed 003 eq. 4.7, its right-hand side eq. 4.4),
// one implicit system per component.
#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "fluid/fv/fv_solver.hpp"

namespace coflow::fluid {

// -div(u u_c) (divergent form) or -(u . grad) u_c = -div(u u_c) + u_c div(u)
// (non-divergent) at the faces of u_c at padded indices n0 + i, i < len, along
// x: the fluxes through the faces of the control volume around each, each the
// advecting velocity (the mean of the two faces beside) times the carried
// value (fv::face_value). The scheme and the form are template arguments so
// that the loop holds no test of them (they were read in it as strings, a
// comparison per face: memcmp took 2.4 % of the fluid's samples in a run of
// the Re 20 cylinder).
template <int DIMS, bool UPWIND, bool DIVERGENT>
void FvSolver::advection_row(const Faces& u, int c, long n0, long len, double* out) const {
  const double* q = u[static_cast<std::size_t>(c)].data();
  const double* v[3] = {u[0].data(), u[1].data(), u[DIMS - 1].data()};
  const long sc = stride(c), s[3] = {stride(0), stride(1), stride(2)};
  const double h[3] = {h_[0], h_[1], h_[2]};
  for (long n = n0; n < n0 + len; ++n) {
    double flux = 0.0, div = 0.0;
    for (int d = 0; d < DIMS; ++d) {
      const long sd = s[d];
      const double up = d == c ? 0.5 * (q[n] + q[n + sd]) : 0.5 * (v[d][n + sd - sc] + v[d][n + sd]);
      const double um = d == c ? 0.5 * (q[n - sd] + q[n]) : 0.5 * (v[d][n - sc] + v[d][n]);
      const double fp = up * fv::face_value(UPWIND, q[n - sd], q[n], q[n + sd], q[n + 2 * sd], up);
      const double fm = um * fv::face_value(UPWIND, q[n - 2 * sd], q[n - sd], q[n], q[n + sd], um);
      flux += (fp - fm) / h[d];
      div += (up - um) / h[d];
    }
    out[n] = DIVERGENT ? -flux : -(flux - q[n] * div);
  }
}

void FvSolver::advection(const Faces& u, Faces& out) const {
  using Row = void (FvSolver::*)(const Faces&, int, long, long, double*) const;
  static constexpr Row rows[2][2][2] = {
      {{&FvSolver::advection_row<2, false, false>, &FvSolver::advection_row<2, false, true>},
       {&FvSolver::advection_row<2, true, false>, &FvSolver::advection_row<2, true, true>}},
      {{&FvSolver::advection_row<3, false, false>, &FvSolver::advection_row<3, false, true>},
       {&FvSolver::advection_row<3, true, false>, &FvSolver::advection_row<3, true, true>}}};
  const Row row = rows[dims_ == 3][p_.advection == "upwind"][p_.form == "divergent"];
  for (int c = 0; c < dims_; ++c) {
    double* o = out[static_cast<std::size_t>(c)].data();
    for_owned_rows([&](const long* at, long n0, long, long len) {
      if (c > 0 && is_boundary_face(c, at[c])) {  // a domain face: not an unknown
        std::fill_n(o + n0, len, 0.0);
        return;
      }
      // Along x only a row's first face can be a domain face (the owned faces
      // are the owned cells' lower ones).
      const long first = c == 0 && is_boundary_face(0, 0) ? 1 : 0;
      if (first == 1) o[n0] = 0.0;
      if (len > first) (this->*row)(u, c, n0 + first, len - first, o);
    });
  }
}

// The implicit system of component c: (a0/dt) u - theta nu lap(u) = rhs, with
// the faces' conditions folded in (they also add to the right-hand side:
// viscous_rhs). A domain face of axis c is not an unknown: its row is 1.
// With an eddy viscosity the matrices are rebuilt every step: the rows whose
// neighbours are all unknowns go by viscous_rows_inside (the same numbers,
// in a loop that vectorises), the others cell by cell here.
void FvSolver::set_viscous(int c, double diag_scale, double theta) {
  fv::StructSystem::Rows& m = rows_;
  m.resize(static_cast<std::size_t>(blk_.owned_cells()));  // every entry written below
  double w[3] = {0.0, 0.0, 0.0};
  for (int d = 0; d < dims_; ++d) w[d] = theta / (h_[d] * h_[d]);
  auto cell = [&](const long* at, long n, long o) {
    double diag = 1.0, lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.0, 0.0, 0.0}, scale = 1.0;
    if (!is_boundary_face(c, at[c])) {
      diag = diag_scale;
      for (int d = 0; d < dims_; ++d) {
        for (int side = 0; side < 2; ++side) {
          const double k = w[d] * nu_face(c, n, d, side);
          double& coupling = side == 0 ? lo[d] : hi[d];
          double& opposite = side == 0 ? hi[d] : lo[d];
          switch (neighbour_kind(c, at, d, side)) {
            case Neighbour::inside:
              diag += k;
              coupling -= k;
              break;
            case Neighbour::wall_tangential:  // ghost = (8U - 6 u0 + u1) / 3
              if (log_law_ && faces_[static_cast<std::size_t>(2 * d + side)].wall) {
                diag += 2 * k;  // the wall functions' ghost 2U - u0: the flux nu_w (u0 - U) / (h/2)
                break;
              }
              diag += 3 * k;
              if (turbulent_) break;  // u1's part on the right-hand side (viscous_rhs)
              opposite -= k / 3;
              scale *= fv::wall_row_scale;
              break;
            case Neighbour::wall_normal:  // the face's value, known
              diag += k;
              break;
            case Neighbour::open:  // zero gradient
              break;
          }
        }
      }
    }
    const auto O = static_cast<std::size_t>(o);
    m.diag[O] = diag * scale;
    for (int d = 0; d < dims_; ++d) {
      m.lower[static_cast<std::size_t>(d)][O] = lo[d] * scale;
      m.upper[static_cast<std::size_t>(d)][O] = hi[d] * scale;
    }
  };
  for_unknown_rows(c, turbulent_, cell,
                   [&](long n, long o, long len) { viscous_rows_inside(c, diag_scale, w, n, o, len, m); });
  viscous_[static_cast<std::size_t>(c)]->take(m);
}

// The rows of u_c's unknowns n + i (owned o + i), i < len, whose neighbours
// are all unknowns: the numbers of set_viscous's cell by cell assembly
// (nu_face's sums in the same order), in a loop that vectorises.
void FvSolver::viscous_rows_inside(int c, double diag_scale, const double (&w)[3], long n, long o, long len,
                                   fv::StructSystem::Rows& m) const {
  const double* nut = nut_.data() + n;
  double* diag_out = m.diag.data() + o;
  const double nu = nu_;
  const long sc = stride(c);
  std::array<double*, 3> lower{}, upper{};
  for (int d = 0; d < 3; ++d) {
    lower[static_cast<std::size_t>(d)] = m.lower[static_cast<std::size_t>(d)].data() + o;
    upper[static_cast<std::size_t>(d)] = m.upper[static_cast<std::size_t>(d)].data() + o;
    if (d >= dims_)
      std::fill_n(lower[static_cast<std::size_t>(d)], len, 0.0),
          std::fill_n(upper[static_cast<std::size_t>(d)], len, 0.0);
  }
  const auto row = [&](auto dims_c, auto c_c) {
    constexpr int DIMS = decltype(dims_c)::value, C = decltype(c_c)::value;
    double* lo[3] = {lower[0], lower[1], lower[2]};
    double* hi[3] = {upper[0], upper[1], upper[2]};
    const long s[3] = {stride(0), stride(1), stride(2)};
#pragma GCC ivdep
    for (long i = 0; i < len; ++i) {
      double diag = diag_scale;
#pragma GCC unroll 3
      for (int d = 0; d < DIMS; ++d) {
        const double k_lo =
            d == C ? w[d] * (nu + nut[i - sc])
                   : w[d] * (nu + 0.25 * ((nut[i - s[d]] + nut[i - s[d] - sc]) + (nut[i] + nut[i - sc])));
        const double k_hi =
            d == C ? w[d] * (nu + nut[i])
                   : w[d] * (nu + 0.25 * ((nut[i] + nut[i - sc]) + (nut[i + s[d]] + nut[i + s[d] - sc])));
        diag += k_lo;
        diag += k_hi;
        lo[d][i] = -k_lo;
        hi[d][i] = -k_hi;
      }
      diag_out[i] = diag;
    }
  };
  using I2 = std::integral_constant<int, 2>;
  using I3 = std::integral_constant<int, 3>;
  using C0 = std::integral_constant<int, 0>;
  using C1 = std::integral_constant<int, 1>;
  using C2 = std::integral_constant<int, 2>;
  if (dims_ == 2)
    c == 0 ? row(I2{}, C0{}) : row(I2{}, C1{});
  else
    c == 0 ? row(I3{}, C0{}) : c == 1 ? row(I3{}, C1{}) : row(I3{}, C2{});
}

// The terms of component c's right-hand side at padded index n that no face
// changes: the history, the extrapolated advection, the explicit part of the
// diffusion, the pressure gradient of the last step, the body force and the
// sources (w: fv::source_weights). One inline function for the rows by a face
// (viscous_rhs) and those inside (viscous_rhs_inside), so that a row does the
// same arithmetic whichever path its rank's block sends it through (the same
// bits as long as the compiler fuses the same multiply-adds in both copies;
// fv's 1-rank-against-N tests have bounds above 0 anyway: the Poisson solves
// differ with the decomposition).
inline double FvSolver::rhs_terms(int c, long n, const fv::Imex& s, double dt, double w_now,
                                  double w_last) const {
  const auto C = static_cast<std::size_t>(c);
  double r = (s.a1 * u_[C][n] - s.a2 * u_old_[C][n]) / dt + s.b0 * adv_[C][n] + s.b1 * adv_old_[C][n];
  if (s.theta < 1) r += (1 - s.theta) * diffusion_at(u_[C], c, n);
  if (steps_ > 0)
    r -= (p_field_[n] - p_field_[n - stride(c)]) / (rho_ * h_[c]);  // the first step: projection
  r += fluid_.body_force[c] / rho_;
  if (ibm_in_rhs_) r += s.a0 / dt * ibm_du_[C][n];  // the immersed boundary's force (force_in_predictor)
  if (have_source_)  // the source as an exact impulse (fv::source_weights)
    r += (w_now * (source_[C][n] + source_[C][n - stride(c)]) +
          w_last * (source_old_[C][n] + source_old_[C][n - stride(c)])) /
         (2 * rho_);
  return r;
}

// Stage in_predictor, before the predictor's solves: ibm_du_ = the forcing's
// change of u~ on the unknowns off the domain's faces (the boundary faces
// hold their values and the forcing does not index them).
void FvSolver::force_in_predictor(const fv::Imex& s, double dt) {
  ibm_in_rhs_ = false;
  if (!ibm_in_predictor_ || !ibm_ || ibm_->empty()) return;
  const double start = MPI_Wtime();
  const auto [w_now, w_last] = fv::source_weights(s, dt, dt_prev_);
  std::array<double*, 3> u{nullptr, nullptr, nullptr};
  for (int c = 0; c < dims_; ++c) {
    const auto C = static_cast<std::size_t>(c);
    ustar_[C] = u_[C];
    auto estimate = [&](long n) {
      ustar_[C][n] =
          dt / s.a0 * (rhs_terms(c, n, s, dt, w_now, w_last) + s.theta * diffusion_at(u_[C], c, n));
    };
    for_unknown_rows(
        c, true,
        [&](const long* at, long n, long) {
          if (!is_boundary_face(c, at[c])) estimate(n);
        },
        [&](long n, long, long len) {
          for (long i = 0; i < len; ++i) estimate(n + i);
        });
    ibm_du_[C] = ustar_[C];
    u[C] = ustar_[C].data();
  }
  ibm_->apply(u, next_time_, velocity_scale_, s.a0 * rho_ / dt, dt);
  for (int c = 0; c < dims_; ++c) {
    const auto C = static_cast<std::size_t>(c);
    for (std::size_t n = 0; n < ibm_du_[C].size(); ++n) ibm_du_[C][n] = ustar_[C][n] - ibm_du_[C][n];
  }
  ibm_in_rhs_ = true;
  ibm_seconds_ += MPI_Wtime() - start;
}

// The right-hand side of component c's row at `at`: rhs_terms and the faces'
// values of the new time.
double FvSolver::viscous_rhs(int c, const long* at, long n, const fv::Imex& s, double dt) const {
  const auto C = static_cast<std::size_t>(c);
  const double t1 = next_time_;
  if (is_boundary_face(c, at[c])) {
    const long g = blk_.owned.lo[c] + at[c];
    const Face& f = faces_[static_cast<std::size_t>(2 * c + (g == 0 ? 0 : 1))];
    return f.kind == Face::open ? u_[C][n]
                                : f.velocity_at(t1)[c] * profile(2 * c + (g == 0 ? 0 : 1), c, at, t1);
  }
  const auto [w_now, w_last] = fv::source_weights(s, dt, dt_prev_);
  double r = rhs_terms(c, n, s, dt, w_now, w_last);
  double scale = 1.0;
  for (int d = 0; d < dims_; ++d) {
    for (int side = 0; side < 2; ++side) {
      const Neighbour kind = neighbour_kind(c, at, d, side);
      if (kind == Neighbour::inside || kind == Neighbour::open) continue;
      const double k = s.theta * nu_face(c, n, d, side) / (h_[d] * h_[d]);
      const double U = faces_[static_cast<std::size_t>(2 * d + side)].velocity_at(t1)[c] *
                       profile(2 * d + side, c, at, t1);
      if (kind == Neighbour::wall_normal) r += k * U;
      if (kind == Neighbour::wall_tangential && log_law_ &&
          faces_[static_cast<std::size_t>(2 * d + side)].wall) {
        r += 2 * k * U;                                               // the wall functions' ghost 2U - u0
      } else if (kind == Neighbour::wall_tangential && turbulent_) {  // u1 extrapolated to the new time
        const long in = side == 0 ? stride(d) : -stride(d);
        r += (8.0 * U + s.e0 * u_[C][n + in] + s.e1 * u_old_[C][n + in]) * k / 3.0;
      } else if (kind == Neighbour::wall_tangential) {
        r += 8.0 / 3.0 * k * U;
        scale *= fv::wall_row_scale;
      }
    }
  }
  return r * scale;
}

// viscous_rhs, and x's start, for the unknowns n0 + i (owned o0 + i), i < len,
// whose neighbours are all unknowns: rhs_terms alone, in a loop that reads no
// face and no neighbour kind (viscous_rhs cell by cell was a tenth of a run).
void FvSolver::viscous_rhs_inside(int c, long n0, long o0, long len, const fv::Imex& s, double dt) {
  const auto [w_now, w_last] = fv::source_weights(s, dt, dt_prev_);
  const double* u = u_[static_cast<std::size_t>(c)].data();
  for (long i = 0; i < len; ++i) {
    rhs_[static_cast<std::size_t>(o0 + i)] = rhs_terms(c, n0 + i, s, dt, w_now, w_last);
    x_[static_cast<std::size_t>(o0 + i)] = u[n0 + i];
  }
}

// A tangential velocity's row next to a wall (or velocity face): the wall
// closure's ghost (8U - 6 u0 + u1) / 3 couples the row to the next unknown in,
// u1, by k_w / 3 besides that unknown's own k_in. With a uniform viscosity the
// row scaled by 3/4 couples to u1 as u1's row couples back (the matrix stays
// symmetric, the closure implicit: fv::wall_row_scale). With an eddy
// viscosity no row scale can do that (k_in / (k_in + k_w / 3) changes along
// the wall and between two walls in a corner), so u1's part goes to the
// right-hand side, extrapolated to the new time as the advection is (b0 u^n +
// b1 u^{n-1}): the matrix stays symmetric, the closure second order in time
// and exact in a steady state.

void FvSolver::momentum(const fv::Imex& s, double dt) {
  advection(u_, adv_);
  if (turbulent_) add_stress_transpose(u_, adv_);
  force_in_predictor(s, dt);
  const double diag = s.a0 / dt, nu_theta = s.theta * nu_;
  double nu_max = nu_;  // the largest nu + nu_t: with turbulence the matrices change every step
  if (turbulent_) {
    for_owned([&](const long*, long n, long) { nu_max = std::max(nu_max, nu_ + nut_[n]); });
    MPI_Allreduce(MPI_IN_PLACE, &nu_max, 1, MPI_DOUBLE, MPI_MAX, comm_);
    viscous_key_ = {0, 0, 0};
  }
  for (int c = 0; c < dims_; ++c) {
    const auto C = static_cast<std::size_t>(c);
    if (viscous_key_[C] != diag || viscous_theta_[C] != nu_theta) {
      const double start = MPI_Wtime();
      // Diagonal dominance: the off-diagonal sum over the diagonal's mass part.
      double off = 0.0;
      for (int d = 0; d < dims_; ++d) off += 4 * s.theta * nu_max / (diag * h_[d] * h_[d]);
      viscous_[C]->use_diagonal(off < 4.0);
      set_viscous(c, diag, s.theta);
      viscous_seconds_ += MPI_Wtime() - start;
      viscous_key_[C] = diag;
      viscous_theta_[C] = nu_theta;
    }
    for_unknown_rows(
        c, true,
        [&](const long* at, long n, long o) {
          rhs_[static_cast<std::size_t>(o)] = viscous_rhs(c, at, n, s, dt);
          x_[static_cast<std::size_t>(o)] = u_[C][n];
        },
        [&](long n, long o, long len) { viscous_rhs_inside(c, n, o, len, s, dt); });
    const double start = MPI_Wtime();
    viscous_[C]->solve(rhs_, x_);
    viscous_seconds_ += MPI_Wtime() - start;
    viscous_iterations_ = std::max(viscous_iterations_, viscous_[C]->last_iterations());
    set_owned(ustar_[C], x_);
  }
  ibm_in_rhs_ = false;
}

}  // namespace coflow::fluid
