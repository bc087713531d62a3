// fv: the transport of k and epsilon (seed 003 eqs. 3.13-3.14) at the cell
// centres, after each step's projection, with the new velocity:
//
//   1. advection, explicit, non-divergent form, the bounded upwind-biased face
//      value (fv::face_value, van Leer's limiter), in sub-steps of Courant
//      number at most 1/2;
//   2. diffusion (nu + nu_t / sigma) implicit, the destruction terms
//      linearised about the old values and implicit (epsilon/k k, C_e2
//      epsilon/k epsilon; Patankar 1980), the production explicit;
//   3. in the two-layer model's one-equation layer (Re_y < Re_y*) epsilon
//      is eq. 3.18's, held in the implicit system as a fixed value.
//
// Positivity by construction: each advection sub-step is a convex
// combination of non-negative values (the limited scheme is TVD for Courant
// numbers up to 1/2, the ghosts are non-negative); the implicit matrix is an
// M-matrix (positive diagonal, non-positive couplings, diagonally dominant)
// and its right-hand side is non-negative (old value, production >= 0), so
// the new k and epsilon are positive (to the linear solver's tolerance). The
// run stops if one is not (it would be a bug, never clipped). Velocity faces
// are inlets only: one that lets fluid out is refused at validation.
#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "fluid/fv/fv_solver.hpp"
#include "fluid/fv/lines.hpp"
#include "fluid/fv/turbulence/closure.hpp"
#include "fluid/fv/turbulence/wall_distance.hpp"

namespace coflow::fluid {

void FvSolver::init_turbulence() {
  turbulent_ = fluid_.turbulence.on;
  if (!turbulent_) return;
  turb_ = fluid_.turbulence;
  log_law_ = turb_.wall == "log-law";
  inlets_ = fluid_.inlet_turbulence(cfg_);
  const std::size_t padded = ex_.field_size();
  k_.assign(padded, turb_.initial_k);
  eps_.assign(padded, turb_.initial_epsilon);
  nut_.assign(padded, 0.0);
  k_change_.assign(padded, 0.0);
  eps_change_.assign(padded, 0.0);
  wall_y_.assign(padded, std::numeric_limits<double>::infinity());
  for_padded([&](const long* at, long n) {
    for (int f = 0; f < 6; ++f) {
      const int a = f / 2;
      if (!faces_[static_cast<std::size_t>(f)].wall || a >= dims_) continue;
      const double g = static_cast<double>(blk_.owned.lo[a] + at[a]) + 0.5;
      const double y = (f % 2 == 0 ? g : static_cast<double>(cells_[a]) - g) * h_[a];
      wall_y_[n] = std::min(wall_y_[n], y);
    }
  });
  box_wall_y_ = wall_y_;
  const std::array<bool, 3> per{periodic_[0], periodic_[1], periodic_[2]};
  k_system_ = std::make_unique<fv::StructSystem>(
      comm_, blk_.owned, cells_, per,
      fv::StructSystem::Options{p_.multigrid, p_.tolerance, p_.max_iterations, "k solve"});
  eps_system_ = std::make_unique<fv::StructSystem>(
      comm_, blk_.owned, cells_, per,
      fv::StructSystem::Options{p_.multigrid, p_.tolerance, p_.max_iterations, "epsilon solve"});
  fv::Closure cl{turb_.constants, nu_, turb_.wall == "two-layer"};
  for_padded([&](const long*, long n) {
    if (cl.one_equation(wall_y_[n], k_[n])) eps_[n] = cl.epsilon_near_wall(wall_y_[n], k_[n]);
  });
  if (log_law_) wall_function_epsilon(scratch_[4]);
  set_inlet_lines(time_);
  fill_scalar_ghosts(k_, inlet_k_, log_law_ ? 1.0 : 0.0, true);
  fill_scalar_ghosts(eps_, inlet_eps_, 1.0, true);
  update_eddy_viscosity();
  check_positive(time_,
                 "fluid.turbulence.initial gives them (k and epsilon positive, nu_t = C_mu k^2 / epsilon a "
                 "finite number)",
                 false);
}

// Immersed bodies are walls too (seed 003 §3.1.2 takes y to the nearest
// wall): each cell's distance is the smaller of the box's walls' and the
// bodies' surface (turbulence/wall_distance.hpp), again whenever the markers
// come (a moving body: every window).
void FvSolver::set_body_wall_distance(const ibm::MarkerSet& markers) {
  const fv::BodyDistance body(markers, fv::BodyDistance::grid_of(cfg_));
  const auto& lower = cfg_.domain.lower;
  // A centre on a body's surface would be at y = 0 (epsilon = 2 nu k / y^2
  // infinite there, and in its neighbours' rows): no closer than a quarter
  // of the smallest spacing, inside the forcing's diffuse surface.
  double floor = h_[0];
  for (int a = 1; a < dims_; ++a) floor = std::min(floor, h_[a]);
  floor *= 0.25;
  for_padded([&](const long* at, long n) {
    std::array<double, 3> x{0, 0, 0};
    for (int a = 0; a < dims_; ++a)
      x[static_cast<std::size_t>(a)] =
          lower[static_cast<std::size_t>(a)] + (static_cast<double>(blk_.owned.lo[a] + at[a]) + 0.5) * h_[a];
    wall_y_[n] = std::min(box_wall_y_[n], std::max(body(x), floor));
  });
  update_eddy_viscosity();  // nu_t of the two-layer model near the bodies
}

// Ghosts of a cell scalar: the neighbours' by exchange; beyond a wall
// wall_sign times the mirrored cell (0: the value 0; -1: odd about the wall),
// beyond a symmetry face the mirrored cell. Beyond an inlet (a velocity face
// with flow through it) and an open face: with `extrapolate` (k, epsilon: the
// advection's upwind-biased face value reads them) the line through the
// inlet's value and the cell inside, or through the last two cells, never
// below zero; without it the inlet's value, or the mirrored cell.
void FvSolver::fill_scalar_ghosts(Field& q, const FaceLines& inlets, double wall_sign, bool extrapolate) {
  ex_.exchange(q);
  for (int a = 0; a < dims_; ++a)
    for (int side = 0; side < 2; ++side) {
      const Face& f = faces_[static_cast<std::size_t>(2 * a + side)];
      if (!f.here || f.kind == Face::periodic) continue;
      const long n = blk_.extent[a];
      const bool in = f.kind == Face::dirichlet && !f.wall, open = f.kind == Face::open;
      fv::for_lines(blk_, a, [&](auto along, const long* line) {
        auto at = [&](long m) { return along(side == 0 ? m : n - 1 - m); };  // m: 0 the first cell in
        const double inlet = in ? inlets.at(2 * a + side, line) : 0.0;
        const double q0 = q[at(0)], q1 = q[at(1)];
        double g1 = q0, g2 = q1;  // mirrored
        if (f.wall) g1 = wall_sign * q0, g2 = wall_sign * q1;
        if (in) g1 = g2 = inlet;
        if (extrapolate && in) g1 = std::max(0.0, 2 * inlet - q0), g2 = std::max(0.0, 2 * inlet - q1);
        if (extrapolate && open) g1 = std::max(0.0, 2 * q0 - q1), g2 = std::max(0.0, 3 * q0 - 2 * q1);
        q[at(-1)] = g1;
        q[at(-2)] = g2;
      });
    }
}

// nu_t at the cells (eqs. 3.17, 3.21-3.25), with its ghosts: odd about a wall
// (zero on it), the inlet's beyond an inlet, mirrored beyond open faces.
void FvSolver::update_eddy_viscosity() {
  const fv::Closure cl{turb_.constants, nu_, turb_.wall == "two-layer"};
  row_work_.resize(static_cast<std::size_t>(3 * blk_.extent[0]));
  for_owned_rows([&](const long*, long n0, long, long len) {
    cl.nu_t_row(wall_y_.data() + n0, k_.data() + n0, eps_.data() + n0, nut_.data() + n0, len,
                row_work_.data());
  });
  fill_scalar_ghosts(nut_, inlet_nut_, -1.0, false);
  if (log_law_) wall_function_ghosts();
}

// k, epsilon and nu_t entering through each face at time t: the face's
// uniform values, or per line (FluidParams::FaceTurbulence::at) from its
// tables at the line's centre on the face, or from the inlet's speed there
// (the face's velocity, ramp and profile factor) and its intensity.
void FvSolver::set_inlet_lines(double t) {
  const fv::Closure cl{turb_.constants, nu_, turb_.wall == "two-layer"};
  auto nut_of = [&](double k, double eps) {
    return k > 0.0 ? cl.nu_t(std::numeric_limits<double>::infinity(), k, eps) : 0.0;
  };
  for (int f = 0; f < 6; ++f) {
    const auto i = static_cast<std::size_t>(f);
    const Face& face = faces_[i];
    const int a = f / 2, o1 = (a + 1) % 3, o2 = (a + 2) % 3;
    auto &K = inlet_k_.values[i], &E = inlet_eps_.values[i], &N = inlet_nut_.values[i];
    if (!inlets_.varies(f) || !face.here || a >= dims_) {
      for (FaceLines* l : {&inlet_k_, &inlet_eps_, &inlet_nut_}) l->per_line[i] = false;
      K.assign(1, inlets_.k[i]), E.assign(1, inlets_.epsilon[i]),
          N.assign(1, nut_of(inlets_.k[i], inlets_.epsilon[i]));
      continue;
    }
    const long stride = blk_.extent[o1] + 2 * blk_.ghost[o1];
    const std::size_t size = static_cast<std::size_t>(stride * (blk_.extent[o2] + 2 * blk_.ghost[o2]));
    const long first = blk_.ghost[o1] + blk_.ghost[o2] * stride;
    K.resize(size), E.resize(size), N.resize(size);
    for (FaceLines* l : {&inlet_k_, &inlet_eps_, &inlet_nut_})
      l->first[i] = first, l->stride[i] = stride, l->per_line[i] = true;
    const Vec3 U = face.velocity_at(t);
    const double w = dims_ == 3 ? U[2] : 0.0;  // in 2D the flow has no z component
    const double speed = std::sqrt(U[0] * U[0] + U[1] * U[1] + w * w);
    const auto& d = cfg_.domain;
    fv::for_lines(blk_, a, [&](auto, const long* line) {
      const auto j = static_cast<std::size_t>(first + line[o1] + line[o2] * stride);
      const double s = inlets_.from_speed(f) ? speed * std::abs(profile(f, a, line, t)) : 0.0;
      double x[3];  // the line's centre on the face, m
      for (int e = 0; e < 3; ++e)
        x[e] = d.lower[e] + (static_cast<double>(blk_.owned.lo[e] + line[e]) + 0.5) * h_[e];
      x[a] = f % 2 == 0 ? d.lower[a] : d.upper[a];
      const auto in = inlets_.at(f, s, x);
      K[j] = in[0], E[j] = in[1], N[j] = nut_of(K[j], E[j]);
    });
  }
}

namespace {

// The largest of |m| and |a[i]|, |b[i]|, i < n: the same number as a
// maximum of doubles when they are finite, infinity where one is not (a
// NaN too: every rank then reduces to infinity and stops alike). A
// non-negative double's bits, read as an unsigned integer, order as the
// number does, and GCC vectorises an integer maximum (a double one only
// under -ffast-math).
double largest_magnitude(const double* __restrict a, const double* __restrict b, long n, double m) {
  constexpr std::uint64_t magnitude = ~(std::uint64_t{1} << 63);  // all but the sign bit
  constexpr auto infinity = std::bit_cast<std::uint64_t>(std::numeric_limits<double>::infinity());
  std::uint64_t top = std::bit_cast<std::uint64_t>(m) & magnitude;
  for (long i = 0; i < n; ++i) {
    const std::uint64_t x = std::bit_cast<std::uint64_t>(a[i]) & magnitude;
    const std::uint64_t y = std::bit_cast<std::uint64_t>(b[i]) & magnitude;
    top = x > top ? x : top;
    top = y > top ? y : top;
  }
  return std::bit_cast<double>(std::min(top, infinity));  // a NaN's bits lie above infinity's
}

// fv::sources over n cells, the same numbers (P: S^2 in, the production out).
void sources_row(const double* __restrict nut, const double* __restrict k, const double* __restrict eps,
                 double ce1, double ce2, double* __restrict P, double* __restrict sink_k,
                 double* __restrict sink_e, double* __restrict source_e, long n) {
  for (long i = 0; i < n; ++i) {
    const double production = nut[i] * P[i], rate = eps[i] / k[i];
    P[i] = production, sink_k[i] = rate, sink_e[i] = ce2 * rate, source_e[i] = ce1 * rate * production;
  }
}

}  // namespace

// The source terms (fv::sources) at the cells n0 + i, i < len, into
// out = {production, sink_k, sink_epsilon, source_epsilon}, with the strain
// rate S^2 = 2 S_ij S_ij (eqs. 3.15-3.16): the normal rates from the cell's
// faces, the shear rates from the centre values of the cells beside (a
// wall's ghosts carry its parabola: the wall's shear). Written out with plain
// pointers and values so that the loops vectorise: a loop over the axes, one
// loop for both parts, or fv::sources's struct kept GCC's loops scalar.
template <int DIMS>
void FvSolver::source_row(double* const (&out)[4], long n0, long len, double (&umax)[3]) const {
  const double ce1 = turb_.constants.C_epsilon1, ce2 = turb_.constants.C_epsilon2;
  const double *__restrict u0 = u_[0].data() + n0, *__restrict u1 = u_[1].data() + n0,
               *__restrict u2 = u_[DIMS - 1].data() + n0;
  const double* __restrict nut = nut_.data() + n0;
  const double* __restrict k = k_.data() + n0;
  const double* __restrict eps = eps_.data() + n0;
  double* __restrict P = out[0] + n0;
  double* __restrict sink_k = out[1] + n0;
  double* __restrict sink_e = out[2] + n0;
  double* __restrict source_e = out[3] + n0;
  const long s0 = stride(0), s1 = stride(1), sz = stride(2);
  const double h0 = inv_h_[0], h1 = inv_h_[1], h2 = inv_h_[2];
  // d u_c / d x_d at cell i (u = u_c, sc and sd the strides, inv = 1 / h_d).
  auto along = [](const double* __restrict u, long sc, double inv, long i) __attribute__((always_inline)) {
    return (u[i + sc] - u[i]) * inv;
  };
  auto across =
      [](const double* __restrict u, long sc, long sd, double inv, long i) __attribute__((always_inline)) {
    return 0.25 * ((u[i + sd] + u[i + sd + sc]) - (u[i - sd] + u[i - sd + sc])) * inv;
  };
  // S^2 into P, its terms in the order of a loop over c < d, in three loops
  // (the rows c = 0, 1 and 2 of that loop): GCC kept the 3D loop scalar in
  // one and its second part in two.
  for (long i = 0; i < len; ++i) {
    const double g00 = along(u0, s0, h0, i);
    const double s01 = across(u0, s0, s1, h1, i) + across(u1, s1, s0, h0, i);
    double s2 = 0.0;
    s2 += 2.0 * g00 * g00;
    s2 += s01 * s01;
    if constexpr (DIMS == 3) {
      const double s02 = across(u0, s0, sz, h2, i) + across(u2, sz, s0, h0, i);
      s2 += s02 * s02;
    }
    P[i] = s2;
  }
  for (long i = 0; i < len; ++i) {
    const double g11 = along(u1, s1, h1, i);
    P[i] += 2.0 * g11 * g11;
  }
  if constexpr (DIMS == 3)
    for (long i = 0; i < len; ++i) {
      const double g22 = along(u2, sz, h2, i), s12 = across(u1, s1, sz, h2, i) + across(u2, sz, s1, h1, i);
      double s2 = P[i];
      s2 += s12 * s12;
      s2 += 2.0 * g22 * g22;
      P[i] = s2;
    }
  // The largest |u_d| on the cells' faces, for the advection's sub-steps,
  // while the row is in cache (a loop of its own: in the one above it kept
  // GCC from vectorising).
  umax[0] = largest_magnitude(u0, u0 + s0, len, umax[0]);
  umax[1] = largest_magnitude(u1, u1 + s1, len, umax[1]);
  if constexpr (DIMS == 3) umax[2] = largest_magnitude(u2, u2 + sz, len, umax[2]);
  sources_row(nut, k, eps, ce1, ce2, P, sink_k, sink_e, source_e, len);
}

// Solve (1/dt + sink) q' - div((nu + nu_t / sigma) grad q') = q / dt + source
// for q' at the cells (q: after advection). Beyond a wall q' = 0 (wall_zero:
// k) or no flux (epsilon), beyond an inlet q' = inlet, no flux beyond open
// and symmetry faces. Cells where `fixed` is set keep their value: their rows
// are the identity and their neighbours take them to the right-hand side (the
// matrix stays symmetric). The first guess is q plus the last step's change
// by this solve, `change` (kept for the next step): about 3 of 8 iterations
// fewer in bench-fv's channel. The rows are assembled along x without a
// branch (assemble_scalar_row), the faces' terms added after
// (add_scalar_face_terms).
void FvSolver::solve_scalar(fv::StructSystem& sys, Field& q, Field& change, const Field& sink,
                            const Field& source, double sigma, const FaceLines& inlet, bool wall_zero,
                            const Field* fixed, double dt) {
  fv::StructSystem::Rows& m = rows_;
  // Every entry that is read is written below (in 2D the third axis's are not read).
  m.resize(static_cast<std::size_t>(blk_.owned_cells()));
  ScalarRows in{q.data(),    change.data(), sink.data(), source.data(), fixed ? fixed->data() : nullptr,
                0.5 / sigma, 1.0 / dt,      &inlet,      wall_zero,     {0.0, 0.0, 0.0}};
  for (int d = 0; d < dims_; ++d) in.inv_h2[d] = 1.0 / (h_[d] * h_[d]);
  int dominant = 1;  // every row's off-diagonal sum below 0.9 of its diagonal
  for_owned_rows([&](const long* at, long n0, long o0, long len) {
    bool edge[3][2] = {};  // the neighbour on that side is beyond a domain face
    for (int d = 0; d < dims_; ++d) {
      const long g = blk_.owned.lo[d] + at[d];
      edge[d][0] = !periodic_[d] && g == 0;
      edge[d][1] = !periodic_[d] && (d == 0 ? g + len : g + 1) == cells_[d];
    }
    if (dims_ == 2)
      in.fixed ? assemble_scalar_row<2, true>(in, m, edge, n0, o0, len)
               : assemble_scalar_row<2, false>(in, m, edge, n0, o0, len);
    else
      in.fixed ? assemble_scalar_row<3, true>(in, m, edge, n0, o0, len)
               : assemble_scalar_row<3, false>(in, m, edge, n0, o0, len);
    add_scalar_face_terms(in, m, edge, at, n0, o0, len);
    dominant &= dims_ == 2 ? diagonally_dominant<2>(m, o0, len) : diagonally_dominant<3>(m, o0, len);
  });
  // Jacobi when the diagonal dominates (a short step), a multigrid V-cycle else.
  MPI_Allreduce(MPI_IN_PLACE, &dominant, 1, MPI_INT, MPI_MIN, comm_);
  sys.use_diagonal(dominant == 1);
  const double start = MPI_Wtime();
  sys.take(m);
  sys.solve(rhs_, x_);
  scalar_solve_seconds_ += MPI_Wtime() - start;
  turbulence_iterations_ = std::max(turbulence_iterations_, sys.last_iterations());
  for_owned_rows([&](const long*, long n0, long o0, long len) {  // one pass, by rows
    double* __restrict dq = change.data() + n0, * __restrict Q = q.data() + n0;
    const double* __restrict X = x_.data() + o0;
    for (long i = 0; i < len; ++i) dq[i] = X[i] - Q[i], Q[i] = X[i];
  });
}

// The rows of the cells n0 + i (owned o0 + i), i < len, along x, as if every
// neighbour were inside: the faces' own terms come after
// (add_scalar_face_terms). A neighbour beyond a domain face (`edge`) gives
// no coupling; a fixed one (FIXED: the two-layer model's epsilon; fixed is 0
// or 1) goes to the right-hand side. Written so that the loop vectorises:
// plain pointers, the edges as factors 0 or 1, and no select of a computed
// value that the compiler would turn into a branch (a fixed cell's diagonal
// is diag (1 - f) + f: exactly 1 or diag).
template <int DIMS, bool FIXED>
void FvSolver::assemble_scalar_row(const ScalarRows& in, fv::StructSystem::Rows& m, const bool (&edge)[3][2],
                                   long n0, long o0, long len) {
  const double* __restrict q = in.q + n0;
  const double* __restrict change = in.change + n0;
  const double* __restrict sink = in.sink + n0;
  const double* __restrict source = in.source + n0;
  const double* __restrict fx = FIXED ? in.fixed + n0 : nullptr;
  const double* __restrict nut = nut_.data() + n0;
  double* __restrict diag_out = m.diag.data() + o0;
  double* __restrict rhs = rhs_.data() + o0;
  double* __restrict x = x_.data() + o0;
  const double nu = nu_, hs = in.half_sigma, inv_dt = in.inv_dt;
  const long first_beyond = edge[0][0] ? 0 : -1, last_beyond = edge[0][1] ? len - 1 : -1;
  const double inside[3][2] = {{1.0, 1.0},  // along x: first_beyond, last_beyond
                               {edge[1][0] ? 0.0 : 1.0, edge[1][1] ? 0.0 : 1.0},
                               {edge[2][0] ? 0.0 : 1.0, edge[2][1] ? 0.0 : 1.0}};
  // One axis's couplings of cell i: D the face's diffusion over h^2.
  auto axis = [&](long i, long s, double in_lo, double in_hi, double inv_h2, double* __restrict lower,
                  double* __restrict upper, double& diag, double& r, double fixed)
      __attribute__((always_inline)) {
    const double D_lo = (nu + (nut[i] + nut[i - s]) * hs) * inv_h2;
    const double D_hi = (nu + (nut[i] + nut[i + s]) * hs) * inv_h2;
    const double f_lo = FIXED ? fx[i - s] : 0.0, f_hi = FIXED ? fx[i + s] : 0.0;
    diag += in_lo * D_lo;
    diag += in_hi * D_hi;
    if (FIXED) {  // a fixed neighbour's value to the right-hand side
      r += in_lo * f_lo * (D_lo * q[i - s]);
      r += in_hi * f_hi * (D_hi * q[i + s]);
    }
    lower[i] = fixed + f_lo == 0.0 && in_lo > 0 ? -D_lo : 0.0;
    upper[i] = fixed + f_hi == 0.0 && in_hi > 0 ? -D_hi : 0.0;
  };
  double* __restrict lower[3];
  double* __restrict upper[3];
  for (int d = 0; d < 3; ++d) {
    lower[d] = m.lower[static_cast<std::size_t>(d)].data() + o0;
    upper[d] = m.upper[static_cast<std::size_t>(d)].data() + o0;
  }
  const long s1 = stride(1), s2 = stride(2);
#pragma GCC ivdep
  for (long i = 0; i < len; ++i) {
    const double fixed = FIXED ? fx[i] : 0.0;
    double diag = inv_dt + sink[i], r = q[i] * inv_dt + source[i];
    axis(i, 1, i != first_beyond ? 1.0 : 0.0, i != last_beyond ? 1.0 : 0.0, in.inv_h2[0], lower[0], upper[0],
         diag, r, fixed);
    axis(i, s1, inside[1][0], inside[1][1], in.inv_h2[1], lower[1], upper[1], diag, r, fixed);
    // In 2D the third axis's couplings are not read (StructSystem, diagonally_dominant).
    if constexpr (DIMS == 3)
      axis(i, s2, inside[2][0], inside[2][1], in.inv_h2[2], lower[2], upper[2], diag, r, fixed);
    diag_out[i] = diag * (1.0 - fixed) + fixed;  // exactly 1 (fixed) or diag
    rhs[i] = r * (1.0 - fixed) + q[i] * fixed;
    x[i] = q[i] + (1.0 - fixed) * change[i];
  }
}

// Whether every row o0 + i, i < len, has its off-diagonal sum below 0.9 of
// its diagonal (DIMS axes: in 2D the third axis's entries are not written).
template <int DIMS>
int FvSolver::diagonally_dominant(const fv::StructSystem::Rows& m, long o0, long len) {
  const double *lo0 = m.lower[0].data() + o0, *lo1 = m.lower[1].data() + o0, *lo2 = m.lower[2].data() + o0;
  const double *up0 = m.upper[0].data() + o0, *up1 = m.upper[1].data() + o0, *up2 = m.upper[2].data() + o0;
  const double* diag = m.diag.data() + o0;
  int all = 1;
  for (long i = 0; i < len; ++i) {
    double off = -((lo0[i] + up0[i]) + (lo1[i] + up1[i]));
    if constexpr (DIMS == 3) off -= lo2[i] + up2[i];
    all &= off < 0.9 * diag[i] ? 1 : 0;
  }
  return all;
}

// The domain faces' terms in a row's free cells: beyond a wall (wall_zero)
// q' = 0 on the wall (nu_t = 0 there), beyond an inlet q' = inlet on the face;
// open, symmetry and epsilon's walls add nothing (no flux).
void FvSolver::add_scalar_face_terms(const ScalarRows& in, fv::StructSystem::Rows& m,
                                     const bool (&edge)[3][2], const long* at, long n0, long o0, long len) {
  for (int d = 0; d < dims_; ++d)
    for (int side = 0; side < 2; ++side) {
      if (!edge[d][side]) continue;
      const Face& f = faces_[static_cast<std::size_t>(2 * d + side)];
      const bool wall = f.wall && in.wall_zero, inlet = f.kind == Face::dirichlet && !f.wall;
      if (!wall && !inlet) continue;
      const long s = side == 0 ? -stride(d) : stride(d);
      const long first = d == 0 ? (side == 0 ? 0 : len - 1) : 0, last = d == 0 ? first + 1 : len;
      for (long i = first; i < last; ++i) {
        const long n = n0 + i;
        const auto O = static_cast<std::size_t>(o0 + i);
        if (in.fixed && in.fixed[n] > 0) continue;
        const double D = (nu_ + (nut_[n] + nut_[n + s]) * in.half_sigma) * in.inv_h2[d];
        const long line[3] = {at[0] + i, at[1], at[2]};  // the cell's (the face's own axis not read)
        if (wall) m.diag[O] += 2 * nu_ * in.inv_h2[d];
        if (inlet) m.diag[O] += 2 * D, rhs_[O] += 2 * D * in.inlet->at(2 * d + side, line);
      }
    }
}

// One step of k and epsilon with the new velocity (see the top of the file).
void FvSolver::turbulence_step(double dt) {
  const double start = MPI_Wtime();
  const fv::Closure cl{turb_.constants, nu_, turb_.wall == "two-layer"};
  const auto& c = turb_.constants;
  const std::size_t padded = k_.size();
  Field& production = scratch_[0];
  Field& sink_k = scratch_[1];
  Field& sink_e = scratch_[2];
  Field& source_e = scratch_[3];
  for (auto& f : scratch_) f.resize(padded);
  set_inlet_lines(next_time_);  // with the velocity's faces at the new time
  double* const out[4] = {production.data(), sink_k.data(), sink_e.data(), source_e.data()};
  double umax[3] = {0.0, 0.0, 0.0};
  for_owned_rows([&](const long*, long n0, long, long len) {
    dims_ == 2 ? source_row<2>(out, n0, len, umax) : source_row<3>(out, n0, len, umax);
  });
  if (log_law_) wall_function_production(production);
  const int sub = scalar_substeps(umax, dt);
  const double k_wall = log_law_ ? 1.0 : 0.0;  // k's ghosts beyond a wall: 0, or mirrored (no flux)
  advect_scalar(k_, inlet_k_, k_wall, dt, sub);
  advect_scalar(eps_, inlet_eps_, 1.0, dt, sub);
  solve_scalar(*k_system_, k_, k_change_, sink_k, production, c.sigma_k, inlet_k_, !log_law_, nullptr, dt);
  fill_scalar_ghosts(k_, inlet_k_, k_wall, true);
  Field& fixed = scratch_[4];
  if (log_law_) wall_function_epsilon(fixed);
  if (cl.two_layer) {
    row_work_.resize(std::max(row_work_.size(), 2 * padded));
    cl.near_wall_row(wall_y_.data(), k_.data(), eps_.data(), fixed.data(), static_cast<long>(padded),
                     row_work_.data());  // every cell, ghosts too: the padded fields as one row
  }
  solve_scalar(*eps_system_, eps_, eps_change_, sink_e, source_e, c.sigma_epsilon, inlet_eps_, false,
               cl.two_layer || log_law_ ? &fixed : nullptr, dt);
  fill_scalar_ghosts(eps_, inlet_eps_, 1.0, true);
  update_eddy_viscosity();
  check_positive(next_time_, "lower fluid.fv.cfl or fluid.fv.max_step", true);
  turbulence_seconds_ += MPI_Wtime() - start;
}

// Stops the run where k or epsilon is not positive, or where k, epsilon or
// nu_t is not finite at time t (`hint`: what to change; `stepped`: after a
// step, where a loss of positivity is a bug): the smallest values by rows
// into locals, a NaN or an infinity found by a sum of 0 x q (the comparisons
// would pass over a NaN). nu_t = C_mu k^2 / epsilon overflows for a huge k
// or a tiny epsilon where both are finite; the momentum solves would then
// take an infinite viscosity.
void FvSolver::check_positive(double t, const std::string& hint, bool stepped) const {
  double low[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), 0.0};
  const double* __restrict K = k_.data(), * __restrict E = eps_.data(), * __restrict N = nut_.data();
  for_owned_rows([&](const long*, long n0, long, long len) {
    double lk = low[0], le = low[1], nan = 0.0;
    for (long n = n0; n < n0 + len; ++n) {
      lk = K[n] < lk ? K[n] : lk;
      le = E[n] < le ? E[n] : le;
      nan += 0.0 * K[n] + 0.0 * E[n] + 0.0 * N[n];
    }
    low[0] = lk, low[1] = le, low[2] += nan;
  });
  low[2] = low[2] == 0.0 ? 0.0 : -1.0;  // -1 where a value is not finite
  MPI_Allreduce(MPI_IN_PLACE, low, 3, MPI_DOUBLE, MPI_MIN, comm_);
  if (low[2] < 0)
    throw std::runtime_error(
        fmt::format("fv: k, epsilon or nu_t is not finite at t = {:.6g} s; {}", t, hint));
  if (!(low[0] > 0 && low[1] > 0) && stepped)
    throw std::runtime_error(
        fmt::format("fv: k-epsilon lost positivity at t = {:.6g} s (min k {:.3g}, min epsilon "
                    "{:.3g}); this is a bug: please report it with the configuration",
                    t, low[0], low[1]));
  if (!(low[0] > 0 && low[1] > 0))
    throw std::runtime_error(fmt::format(
        "fv: k and epsilon must be positive at t = {:.6g} s (min k {:.3g}, min epsilon {:.3g}); {}", t,
        low[0], low[1], hint));
}

}  // namespace coflow::fluid
