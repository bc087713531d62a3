#include "fluid/fv_reference/fv_reference.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <stdexcept>

#include "coflow/output.hpp"
#include "fluid/fv/fv_solver.hpp"
#include "fluid/grid/cell_fields.hpp"

namespace coflow::fluid {

FvReference::FvReference(const Setup& s, const Params& p)
    : comm_(s.comm), cfg_(s.cfg), fluid_(s.params), opt_(p) {
  if (s.decomposition.ranks() != 1) throw std::runtime_error("fv-reference is serial: set fluid.ranks: 1");
  const auto& d = cfg_.domain;
  const auto h = d.spacing();
  dims_ = d.cells[2] == 1 ? 2 : 3;
  for (int a = 0; a < 3; ++a) {
    n_[a] = d.cells[a];
    g_[a] = n_[a] > 1 ? 2 : 0;
    m_[a] = n_[a] + 2 * g_[a];
    h_[a] = h[a];
  }
  box_ = s.decomposition.block(0);
  nu_ = fluid_.viscosity;
  rho_ = fluid_.density;
  for (int f = 0; f < 6; ++f) {
    const BoundaryParams b = fluid_.boundary(f, cfg_);
    Side& side = sides_[f];
    if (b.type == "periodic" || n_[f / 2] == 1) continue;
    side.ramp = b.ramp;
    side.kind = b.type == "symmetry"                         ? Kind::symmetry
                : (b.type == "wall" || b.type == "velocity") ? Kind::wall
                                                             : Kind::open;
    if (b.type == "velocity") side.velocity = {b.value.values[0], b.value.values[1], b.value.values[2]};
    side.boundary = b;
    if (b.type == "pressure") side.pressure = b.value.values[0];
    side.pressure_face = b.type == "pressure";
    has_open_ = has_open_ || side.kind == Kind::open;
  }
  boundary_speed_ = fv::boundary_speeds(fluid_, cfg_);
  const std::size_t size = static_cast<std::size_t>(m_[0] * m_[1] * m_[2]);
  for (auto* f : {&u_, &u_old_, &adv_, &adv_old_, &source_, &source_old_})
    for (auto& c : *f) c.assign(size, 0.0);
  p_.assign(size, 0.0);
  phi_.assign(size, 0.0);
  phi_old_.assign(size, 0.0);
  // The initial state at the faces (velocity) and centres (pressure), ghosts included.
  for (long k = -g_[2]; k < n_[2] + g_[2]; ++k)
    for (long j = -g_[1]; j < n_[1] + g_[1]; ++j)
      for (long i = -g_[0]; i < n_[0] + g_[0]; ++i) {
        const long x[3] = {i, j, k};
        Vec3 u, pos;
        double pr;
        for (int c = 0; c < dims_; ++c) {
          for (int a = 0; a < 3; ++a) pos[a] = d.lower[a] + (x[a] + (a == c ? 0.0 : 0.5)) * h_[a];
          fluid_.initial_state(cfg_, pos, u, pr);
          u_[static_cast<std::size_t>(c)][static_cast<std::size_t>(at(x))] = u[c];
        }
        for (int a = 0; a < 3; ++a) pos[a] = d.lower[a] + (x[a] + 0.5) * h_[a];
        fluid_.initial_state(cfg_, pos, u, pr);
        p_[static_cast<std::size_t>(at(x))] = pr;
      }
  // The wall functions' ghosts from the first step on (turbulence_init sets
  // the same flag again).
  log_law_ = fluid_.turbulence.on && fluid_.turbulence.wall == "log-law";
  velocity_ghosts(u_, 0.0, true, false);
  turbulence_init();
}

Vec3 FvReference::side_velocity(int face, double t) const {
  const Side& s = sides_[face];
  const double r = s.ramp > 0 ? std::min(1.0, t / s.ramp) : 1.0;
  return s.ramp > 0 ? Vec3{s.velocity[0] * r, s.velocity[1] * r, s.velocity[2] * r} : s.velocity;
}

double FvReference::side_pressure(int face, double t) const {
  const Side& s = sides_[face];
  return s.ramp > 0 ? s.pressure * std::min(1.0, t / s.ramp) : s.pressure;
}

// A velocity face's profile factor at u_c's place x (a c-face; the other
// components at centres) at time t: BoundaryParams::profile_factor at its
// fractions of the box.
double FvReference::profile(int face, int c, const long* x, double t) const {
  double s[3];
  for (int e = 0; e < 3; ++e) s[e] = (static_cast<double>(x[e]) + (e == c ? 0.0 : 0.5)) / static_cast<double>(n_[e]);
  return sides_[face].boundary.profile_factor(face, s, cfg_, t);
}

// Faces on the domain's boundary along a non-periodic axis are not unknowns.
bool FvReference::unknown(int c, long i) const {
  return sides_[2 * c].kind == Kind::periodic || (i > 0 && i < n_[c]);
}

// The velocity's ghosts, axis after axis over the whole padded extent of the
// others: periodic copies, or the face's condition (fv's boundaries.cpp has
// the same rules: the normal component on a wall is its value and odd about
// it; a tangential one takes the parabola through the wall and two cells; an
// open face has zero gradient).
void FvReference::velocity_ghosts(Faces& u, double t, bool keep_open, bool zero) const {
  for (int a = 0; a < dims_; ++a) {
    const long n = n_[a], s = step_of(a);
    for_lines(a, [&](long o, const long* x) {  // o, x: index 0 along a on the line
      auto q = [&](Field& f, long m) -> double& { return f[static_cast<std::size_t>(o + m * s)]; };
      for (int c = 0; c < dims_; ++c) {
        Field& f = u[static_cast<std::size_t>(c)];
        if (sides_[2 * a].kind == Kind::periodic) {
          q(f, -1) = q(f, n - 1), q(f, -2) = q(f, n - 2), q(f, n) = q(f, 0), q(f, n + 1) = q(f, 1);
          continue;
        }
        for (int side = 0; side < 2; ++side) {
          const Side& sd = sides_[2 * a + side];
          const double v = zero ? 0.0 : side_velocity(2 * a + side, t)[c] * profile(2 * a + side, c, x, t);
          const long b = side == 0 ? 0 : n - 1, dir = side == 0 ? -1 : 1;  // last cell, outwards
          if (sd.kind == Kind::symmetry && c != a) {                       // mirrored: no shear
            q(f, b + dir) = q(f, b);
            q(f, b + 2 * dir) = q(f, b - dir);
          } else if (sd.kind != Kind::open && c == a) {  // the face's value (symmetry: 0), odd about it
            const long face = side == 0 ? 0 : n;
            q(f, face) = v;
            q(f, face + dir) = 2 * v - q(f, face - dir);
            if (side == 0) q(f, -2) = 2 * v - q(f, 2);
          } else if (sd.kind == Kind::wall && log_law_ &&
                     !is_inlet(2 * a + side)) {  // the wall functions' line
            q(f, b + dir) = 2 * v - q(f, b);
            q(f, b + 2 * dir) = 2 * v - q(f, b - dir);
          } else if (sd.kind == Kind::wall) {
            q(f, b + dir) = fv::wall_ghost(v, q(f, b), q(f, b - dir));
            q(f, b + 2 * dir) = fv::wall_ghost2(v, q(f, b), q(f, b - dir));
          } else if (c == a) {
            const long face = side == 0 ? 0 : n;
            if (!keep_open) q(f, face) = q(f, face - dir);
            q(f, face + dir) = q(f, face);
            if (side == 0) q(f, -2) = q(f, 0);
          } else {
            q(f, b + dir) = q(f, b + 2 * dir) = q(f, b);
          }
        }
      }
    });
  }
}

// -div(u u_c), or -(u . grad) u_c, at the face of u_c with index n: for each
// axis d the two faces of the control volume around it, each carrying the
// mean of the two advecting faces beside it times fv::face_value.
double FvReference::advection_at(const Faces& u, int c, long n) const {
  const Field& q = u[static_cast<std::size_t>(c)];
  const bool upwind = opt_.advection == "upwind";
  auto Q = [&](long m) { return q[static_cast<std::size_t>(m)]; };
  double flux = 0.0, div = 0.0;
  for (int d = 0; d < dims_; ++d) {
    const long s = step_of(d), sc = step_of(c);
    const Field& v = u[static_cast<std::size_t>(d)];
    auto V = [&](long m) { return v[static_cast<std::size_t>(m)]; };
    double up, um;
    if (d == c) {
      up = 0.5 * (Q(n) + Q(n + s));
      um = 0.5 * (Q(n - s) + Q(n));
    } else {
      up = 0.5 * (V(n + s - sc) + V(n + s));
      um = 0.5 * (V(n - sc) + V(n));
    }
    const double fp = up * fv::face_value(upwind, Q(n - s), Q(n), Q(n + s), Q(n + 2 * s), up);
    const double fm = um * fv::face_value(upwind, Q(n - 2 * s), Q(n - s), Q(n), Q(n + s), um);
    flux += (fp - fm) / h_[d];
    div += (up - um) / h_[d];
  }
  return opt_.form == "divergent" ? -flux : -(flux - Q(n) * div);
}

double FvReference::laplacian_at(const Field& q, long n) const {
  double l = 0.0;
  for (int d = 0; d < dims_; ++d) {
    const long s = step_of(d);
    l += (q[static_cast<std::size_t>(n + s)] - 2 * q[static_cast<std::size_t>(n)] +
          q[static_cast<std::size_t>(n - s)]) /
         (h_[d] * h_[d]);
  }
  return l;
}

// The weight of a row next to walls along axes other than c that makes the
// operator with the wall closure symmetric: 3/4 per wall for a uniform
// viscosity (fv::wall_row_scale); with an eddy viscosity 1, the closure's u1
// part taken to the right-hand side instead (deferred_wall).
double FvReference::wall_weight(int c, const long x[3], long) const {
  double w = 1.0;
  for (int d = 0; d < dims_; ++d) {
    if (d == c) continue;
    for (int side = 0; side < 2; ++side) {
      if (x[d] != (side == 0 ? 0 : n_[d] - 1) || sides_[2 * d + side].kind != Kind::wall) continue;
      if (!turbulent_) w *= fv::wall_row_scale;  // with nu_t: u1's part lagged (deferred_wall)
    }
  }
  return w;
}

void FvReference::pressure_ghosts(Field& p, const double open_value[6]) const {
  for (int a = 0; a < dims_; ++a) {
    const long n = n_[a], s = step_of(a);
    for_lines(a, [&](long o, const long*) {
      auto q = [&](long m) -> double& { return p[static_cast<std::size_t>(o + m * s)]; };
      if (sides_[2 * a].kind == Kind::periodic) {
        q(-1) = q(n - 1), q(-2) = q(n - 2), q(n) = q(0), q(n + 1) = q(1);
        return;
      }
      for (int side = 0; side < 2; ++side) {
        const bool open = sides_[2 * a + side].kind == Kind::open;
        for (long g = 1; g <= 2; ++g) {
          const long ghost = side == 0 ? -g : n - 1 + g, mirror = side == 0 ? g - 1 : n - g;
          q(ghost) = open ? 2 * open_value[2 * a + side] - q(mirror) : q(mirror);
        }
      }
    });
  }
}

double FvReference::divergence_at(const Faces& u, long n) const {
  double div = 0.0;
  for (int c = 0; c < dims_; ++c) {
    const Field& q = u[static_cast<std::size_t>(c)];
    div += (q[static_cast<std::size_t>(n + step_of(c))] - q[static_cast<std::size_t>(n)]) / h_[c];
  }
  return div;
}

// theta k_w u1 / 3 summed over the walls along axes other than c beside u_c's
// face n (x: its cell), k_w = (nu + nu_t on the wall's side) / h^2, u1 =
// value(the next face in): the wall closure's part that fv takes to the
// right-hand side with an eddy viscosity (fv's momentum.cpp).
template <class Value>
double FvReference::deferred_wall(int c, const long x[3], long n, double theta, Value&& value) const {
  double r = 0.0;
  for (int d = 0; d < dims_; ++d) {
    if (d == c) continue;
    for (int side = 0; side < 2; ++side) {
      if (x[d] != (side == 0 ? 0 : n_[d] - 1) || sides_[2 * d + side].kind != Kind::wall) continue;
      if (log_law_ && !is_inlet(2 * d + side)) continue;  // the wall functions' ghost has no u1 part
      const long in = side == 0 ? step_of(d) : -step_of(d);
      r += theta * nu_at(c, n, d, side) / (h_[d] * h_[d]) * value(n + in) / 3.0;
    }
  }
  return r;
}

// Row c of the momentum predictor's right-hand side at face n (x: its cell),
// before the wall weight: the history, the advection, the explicit part of
// the diffusion, the old pressure, the body force, the source's impulse;
// with an eddy viscosity, deferred: the wall closures' u1 part.
double FvReference::predictor_rhs(int c, const long* x, long n, const fv::Imex& s, double dt,
                                  bool with_pressure, bool deferred) const {
  const auto C = static_cast<std::size_t>(c);
  const auto N = static_cast<std::size_t>(n);
  const long sc = step_of(c);
  double r = (s.a1 * u_[C][N] - s.a2 * u_old_[C][N]) / dt + s.b0 * adv_[C][N] + s.b1 * adv_old_[C][N];
  if (s.theta < 1) r += (1 - s.theta) * viscous_at(u_[C], c, n);
  if (with_pressure) r -= (p_[N] - p_[static_cast<std::size_t>(n - sc)]) / (rho_ * h_[c]);
  r += fluid_.body_force[c] / rho_;
  const auto [w_now, w_last] = fv::source_weights(s, dt, dt_prev_);  // the source's impulse, exactly
  const auto below = static_cast<std::size_t>(n - sc);
  r += (w_now * (source_[C][N] + source_[C][below]) + w_last * (source_old_[C][N] + source_old_[C][below])) /
       (2 * rho_);
  if (turbulent_ && deferred)
    r += deferred_wall(c, x, n, s.theta, [&](long m) {
      return s.e0 * u_[C][static_cast<std::size_t>(m)] + s.e1 * u_old_[C][static_cast<std::size_t>(m)];
    });
  return r;
}

// u* to the advection's, diffusion's and old pressure's provisional velocity,
// each component's implicit system solved by conjugate gradients. The
// immersed boundary forces u* after the solve (stage after_predictor, seed
// 003 eqs. 4.7-4.11) or adds its force to the right-hand sides, the force
// found on the explicit estimate of u* (stage in_predictor: fv's
// force_in_predictor).
void FvReference::momentum(const fv::Imex& s, double dt, bool with_pressure) {
  for (int c = 0; c < dims_; ++c)
    each_cell([&](const long* x, std::size_t n) {
      adv_[static_cast<std::size_t>(c)][n] =
          unknown(c, x[c]) ? advection_at(u_, c, static_cast<long>(n)) +
                                 (turbulent_ ? stress_transpose_at(u_, c, static_cast<long>(n)) : 0.0)
                           : 0.0;
    });
  Faces rhs;
  for (int c = 0; c < dims_; ++c) {
    rhs[static_cast<std::size_t>(c)].assign(u_[0].size(), 0.0);
    each_cell([&](const long* x, std::size_t n) {
      if (unknown(c, x[c]))
        rhs[static_cast<std::size_t>(c)][n] =
            predictor_rhs(c, x, static_cast<long>(n), s, dt, with_pressure, true);
    });
  }
  const bool in_predictor = ibm_ && !ibm_->empty() && ibm_stage_ == "in_predictor";
  if (in_predictor) {  // u* estimated with the implicit diffusion at u^n (its ghosts), forced; the force to
                       // the rows
    Faces estimate = u_;
    for (int c = 0; c < dims_; ++c)
      each_cell([&](const long* x, std::size_t n) {
        const auto C = static_cast<std::size_t>(c);
        const long N = static_cast<long>(n);
        if (unknown(c, x[c]))
          estimate[C][n] =
              dt / s.a0 *
              (predictor_rhs(c, x, N, s, dt, with_pressure, false) + s.theta * viscous_at(u_[C], c, N));
      });
    Faces forced = estimate;
    force_immersed(forced, s, dt);
    for (int c = 0; c < dims_; ++c)
      each_cell([&](const long* x, std::size_t n) {
        const auto C = static_cast<std::size_t>(c);
        if (unknown(c, x[c])) rhs[C][n] += s.a0 / dt * (forced[C][n] - estimate[C][n]);
      });
  }
  Faces star = u_;
  for (int c = 0; c < dims_; ++c) solve_predictor(c, s, dt, rhs[static_cast<std::size_t>(c)], star);
  if (!in_predictor) force_immersed(star, s, dt);
  velocity_ghosts(star, next_time_, false, false);  // walls' values, open faces extrapolated
  if (convect_outflow(star, dt)) velocity_ghosts(star, next_time_, true, false);
  u_old_.swap(u_);
  u_.swap(star);  // u_ holds u* until the projection
}

// Component c of u* into star: weight (a0/dt x - theta div((nu + nu_t) grad
// x)) = weight rhs, by conjugate gradients.
void FvReference::solve_predictor(int c, const fv::Imex& s, double dt, Field rhs, Faces& star) {
  const double t1 = next_time_;
  const auto C = static_cast<std::size_t>(c);
  std::vector<long> rows;
  Field weight(u_[C].size(), 0.0);
  each_cell([&](const long* x, std::size_t n) {
    if (!unknown(c, x[c])) return;
    const long N = static_cast<long>(n);
    rows.push_back(N);
    weight[n] = wall_weight(c, x, N);
    rhs[n] *= weight[n];
  });
  // A x = weight (a0/dt x - theta nu lap x); the faces' values make it affine:
  // A(x) = A_lin(x) + A(0), so A_lin x = rhs - A(0).
  auto apply = [&](const Field& xf, Field& y, bool zero) {
    Faces X;
    for (auto& f : X) f.assign(xf.size(), 0.0);
    for (long i : rows) X[C][static_cast<std::size_t>(i)] = xf[static_cast<std::size_t>(i)];
    velocity_ghosts(X, t1, false, zero);
    for (long i : rows) {
      const auto I = static_cast<std::size_t>(i);
      y[I] = weight[I] * (s.a0 / dt * X[C][I] - s.theta * viscous_at(X[C], c, i));
      if (turbulent_) {  // the ghosts' u1 part is not the operator's (on the right-hand side)
        const long xi[3] = {i % m_[0] - g_[0], (i / m_[0]) % m_[1] - g_[1], i / (m_[0] * m_[1]) - g_[2]};
        y[I] += deferred_wall(c, xi, i, s.theta, [&](long m) { return X[C][static_cast<std::size_t>(m)]; });
      }
    }
  };
  Field zero(rhs.size(), 0.0), affine(rhs.size(), 0.0);
  apply(zero, affine, false);
  for (long i : rows) rhs[static_cast<std::size_t>(i)] -= affine[static_cast<std::size_t>(i)];
  Field x = u_[C];
  conjugate_gradients([&](const Field& a, Field& y) { apply(a, y, true); }, rows, x, rhs, "viscous solve");
  for (long i : rows) star[C][static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)];
}

// An outflow face's normal velocity before the projection: du/dt + U du/dn = 0
// with U the face's mean outward velocity of the last step (fv's
// boundaries.cpp), upwind from the first face inside. False: no outflow face.
bool FvReference::convect_outflow(Faces& star, double dt) const {
  bool any = false;
  for (int face = 0; face < 6; ++face) {
    const int a = face / 2, side = face % 2;
    if (a >= dims_ || sides_[face].kind != Kind::open || sides_[face].pressure_face) continue;
    any = true;
    const auto A = static_cast<std::size_t>(a);
    const long s = step_of(a), b = side == 0 ? 0 : n_[a];  // the boundary face's index along a
    const long in = side == 0 ? 1 : -1;                    // towards the first face inside
    double sum = 0.0;
    each_cell([&](const long* x, std::size_t n) {
      if (x[a] != 0) return;
      const double v = u_[A][n + static_cast<std::size_t>(b * s)];
      sum += side == 0 ? -v : v;
    });
    const double U = std::max(0.0, sum / static_cast<double>(n_[0] * n_[1] * n_[2] / n_[a]));
    each_cell([&](const long* x, std::size_t n) {
      if (x[a] != 0) return;
      const auto face_at = n + static_cast<std::size_t>(b * s),
                 inside = face_at + static_cast<std::size_t>(in * s);
      star[A][face_at] = u_[A][face_at] - dt / h_[a] * U * (u_[A][face_at] - u_[A][inside]);
    });
  }
  return any;
}

// u = u* - dt / (rho a0) grad(phi) on the unknown faces and the open ones.
void FvReference::correct(Faces& u, double factor) const {
  for (int c = 0; c < dims_; ++c) {
    Field& q = u[static_cast<std::size_t>(c)];
    const long sc = step_of(c);
    each_cell([&](const long* x, std::size_t n) {
      const long N = static_cast<long>(n);
      auto phi = [&](long m) { return phi_[static_cast<std::size_t>(m)]; };
      if (unknown(c, x[c]) || (x[c] == 0 && sides_[2 * c].kind == Kind::open))
        q[n] -= (phi(N) - phi(N - sc)) / (factor * h_[c]);
      if (x[c] == n_[c] - 1 && sides_[2 * c + 1].kind == Kind::open)
        q[static_cast<std::size_t>(N + sc)] -= (phi(N + sc) - phi(N)) / (factor * h_[c]);
    });
  }
}

// The projection of fv (projection.cpp), with the Poisson operator applied
// cell by cell: -lap(phi) = -(rho a0 / dt) div(u*), phi on an open face its
// pressure change (the pressure itself on the first step).
void FvReference::project(const fv::Imex& s, double dt, bool incremental) {
  const double t0 = time_, t1 = next_time_, factor = rho_ * s.a0 / dt;
  double change[6] = {0, 0, 0, 0, 0, 0}, none[6] = {0, 0, 0, 0, 0, 0};
  for (int f = 0; f < 6; ++f)
    if (sides_[f].kind == Kind::open)
      change[f] = side_pressure(f, t1) - (incremental ? side_pressure(f, t0) : 0.0);
  std::vector<long> rows;
  Field rhs(p_.size(), 0.0);
  double sum = 0.0;
  each_cell([&](const long*, std::size_t n) {
    rows.push_back(static_cast<long>(n));
    rhs[n] = -factor * divergence_at(u_, static_cast<long>(n));
  });
  // The affine part (open faces' change), moved to the right-hand side.
  Field zero(p_.size(), 0.0);
  pressure_ghosts(zero, change);
  for (long i : rows) {
    rhs[static_cast<std::size_t>(i)] += laplacian_at(zero, i);
    sum += rhs[static_cast<std::size_t>(i)];
  }
  double hmin = h_[0];  // fv's floor: a divergence of 1e-6 tolerance U / h per cell
  for (int d = 1; d < dims_; ++d) hmin = std::min(hmin, h_[d]);
  if (!has_open_) {
    fv::check_closed_balance(sum, static_cast<double>(rows.size()), factor, velocity_scale_, hmin);
    for (long i : rows) rhs[static_cast<std::size_t>(i)] -= sum / static_cast<double>(rows.size());
  }
  Field x = incremental ? phi_ : p_;
  auto apply = [&](const Field& a, Field& y) {
    Field q = a;
    pressure_ghosts(q, none);
    for (long i : rows) y[static_cast<std::size_t>(i)] = -laplacian_at(q, i);
  };
  const double floor = 1e-6 * opt_.tolerance * factor * velocity_scale_ / hmin *
                       std::sqrt(static_cast<double>(rows.size()));
  conjugate_gradients(apply, rows, x, rhs, "pressure Poisson solve", floor);
  if (!has_open_) {
    double mean = 0.0;
    for (long i : rows) mean += x[static_cast<std::size_t>(i)];
    mean /= static_cast<double>(rows.size());
    for (long i : rows) x[static_cast<std::size_t>(i)] -= mean;
  }
  phi_old_.swap(phi_);  // kept only for fv's checkpoint format (fv extrapolates its first guess)
  phi_ = x;
  pressure_ghosts(phi_, change);
  correct(u_, factor);
  for (long i : rows) {
    const auto I = static_cast<std::size_t>(i);
    p_[I] = incremental ? p_[I] + phi_[I] : phi_[I];
  }
  double face_p[6];
  for (int f = 0; f < 6; ++f) face_p[f] = side_pressure(f, t1);
  pressure_ghosts(p_, face_p);
  velocity_ghosts(u_, t1, true, false);
}

void FvReference::advance(double window) {
  first_window_ = steps_ == 0;
  marker_speed_ = markers_speed_.over(window);
  const double end = time_ + window;
  window_steps_ = 0;
  poisson_iterations_ = 0;
  long left = 0;
  double dt = 0.0;
  while (end - time_ > 1e-12 * window) {
    double umax[3] = {0, 0, 0};
    velocity_maxima(umax);
    velocity_scale_ = std::max({umax[0], umax[1], umax[2]});
    if (first_window_) fv::raise_to(umax, boundary_speed_, marker_speed_);
    double limit = fv::cfl_step(opt_.cfl, umax, h_, dims_);
    if (opt_.max_step > 0) limit = std::min(limit, opt_.max_step);
    if (left == 0 || dt > limit) {
      dt = fv::next_step(limit, dt_prev_, end - time_);
      left = fv::steps_left(end - time_, dt, "fv-reference");
    }
    const double omega = dt_prev_ > 0 ? dt / dt_prev_ : 1.0;
    const fv::Imex s = steps_ == 0            ? fv::Imex::first()
                       : opt_.time == "cnab2" ? fv::Imex::cnab2(omega)
                                              : fv::Imex::sbdf2(omega);
    next_time_ = left == 1 ? end : time_ + dt;  // the window's last step lands on its end exactly
    momentum(s, dt, steps_ > 0);
    project(s, dt, steps_ > 0);
    if (turbulent_) turbulence_step(dt);
    adv_old_.swap(adv_);
    source_old_ = source_;
    dt_prev2_ = dt_prev_;
    dt_prev_ = last_dt_ = dt;
    time_ = next_time_;
    ++steps_;
    ++window_steps_;
    if (--left == 0) break;
  }
  double umax[3] = {0, 0, 0};
  velocity_maxima(umax);  // the window's last step checked before its output
}

// The largest |u_c| over the faces; throws where a value is not finite.
void FvReference::velocity_maxima(double umax[3]) const {
  bool finite = true;
  for (int c = 0; c < dims_; ++c)
    each_cell([&](const long*, std::size_t n) {
      const auto& q = u_[static_cast<std::size_t>(c)];
      const double a = std::abs(q[n]), b = std::abs(q[n + static_cast<std::size_t>(step_of(c))]);
      finite = finite && std::isfinite(a) && std::isfinite(b);
      umax[c] = std::max({umax[c], a, b});
    });
  if (!finite)
    throw std::runtime_error(fmt::format("fv-reference: the velocity is not finite at t = {:.6g} s", time_));
}

std::vector<output::GridField> FvReference::fields(const config::StringList& names) {
  const std::size_t N = static_cast<std::size_t>(n_[0] * n_[1] * n_[2]);
  out_u_.assign(3 * N, 0.0);
  out_p_.assign(N, 0.0);
  out_rho_.assign(N, rho_);
  out_div_.assign(N, 0.0);
  std::size_t o = 0;
  each_cell([&](const long*, std::size_t n) {
    for (int c = 0; c < dims_; ++c) {
      const Field& q = u_[static_cast<std::size_t>(c)];
      out_u_[3 * o + static_cast<std::size_t>(c)] =
          0.5 * (q[n] + q[n + static_cast<std::size_t>(step_of(c))]);
    }
    out_p_[o] = p_[n];
    out_div_[o] = divergence_at(u_, static_cast<long>(n));
    ++o;
  });
  out_k_.assign(N, 0.0), out_eps_.assign(N, 0.0), out_nut_.assign(N, 0.0);
  o = 0;
  each_cell([&](const long*, std::size_t n) {
    if (turbulent_) out_k_[o] = k_[n], out_eps_[o] = eps_[n], out_nut_[o] = nut_[n];
    ++o;
  });
  out_yplus_ = y_plus();
  return FvSolver::named_fields(names,
                                {out_u_, out_p_, out_rho_, out_div_, out_k_, out_eps_, out_nut_, out_yplus_});
}

Diagnostics FvReference::diagnostics() {
  fields({});
  Diagnostics d = FvSolver::cell_diagnostics(out_u_, rho_ * h_[0] * h_[1] * h_[2]);
  double div = 0.0;
  for (double v : out_div_) div = std::max(div, std::abs(v));
  d.extra = {static_cast<double>(window_steps_), last_dt_, 0.0, 0.0, div};
  if (turbulent_) {  // fv's turbulence columns (the iterations not counted: 0)
    double km = 0, em = 0, nut = 0, yp = 0;
    for (std::size_t o = 0; o < out_k_.size(); ++o) {
      km += out_k_[o] / static_cast<double>(out_k_.size());
      em += out_eps_[o] / static_cast<double>(out_k_.size());
      nut = std::max(nut, out_nut_[o]);
      yp = std::max(yp, out_yplus_[o]);
    }
    d.extra.insert(d.extra.end(), {km, em, nut, yp, 0.0});
  }
  return d;
}

std::vector<output::Series::Column> FvReference::series_columns() const {
  return FvSolver::columns(turbulent_);
}

void FvReference::set_source(std::span<const double> force_density) {
  std::size_t o = 0;
  each_cell([&](const long*, std::size_t n) {
    for (std::size_t c = 0; c < 3; ++c) source_[c][n] = force_density[3 * o + c];
    ++o;
  });
  wrap_cells(source_);
}

// The ghost below the first cell along each periodic axis (a face of the first
// cells reads the cell below).
void FvReference::wrap_cells(Faces& f) const {
  for (int a = 0; a < dims_; ++a)
    if (sides_[2 * a].kind == Kind::periodic)
      each_cell([&](const long* x, std::size_t n) {
        if (x[a] != n_[a] - 1) return;
        for (auto& c : f) c[n - static_cast<std::size_t>(step_of(a) * n_[a])] = c[n];
      });
}

// fv's checkpoint format (fv_state.cpp), so that either variant restarts the other's.
void FvReference::save(const std::string& dir) {
  const std::size_t N = static_cast<std::size_t>(n_[0] * n_[1] * n_[2]);
  std::vector<double> u(3 * N), top(3 * N, 0.0), old(3 * N), adv(3 * N), src(3 * N), p(N), phi(N), phi_old(N);
  std::size_t o = 0;
  each_cell([&](const long* x, std::size_t n) {
    for (std::size_t c = 0; c < 3; ++c) {
      u[3 * o + c] = u_[c][n];
      old[3 * o + c] = u_old_[c][n];
      adv[3 * o + c] = adv_old_[c][n];
      src[3 * o + c] = source_old_[c][n];
      const int C = static_cast<int>(c);
      if (C < dims_ && x[C] == n_[C] - 1 && sides_[2 * C + 1].kind == Kind::open)
        top[3 * o + c] = u_[c][n + static_cast<std::size_t>(step_of(C))];
    }
    p[o] = p_[n];
    phi[o] = phi_[n];
    phi_old[o] = phi_old_[n];
    ++o;
  });
  grid::save_cell_fields(comm_, dir + "/fv.h5", time_, steps_, {n_[0], n_[1], n_[2]}, box_,
                         {{"velocity_faces", 3, u},
                          {"velocity_upper", 3, top},
                          {"velocity_previous", 3, old},
                          {"advection_previous", 3, adv},
                          {"pressure", 1, p},
                          {"pressure_increment", 1, phi},
                          {"pressure_increment_previous", 1, phi_old},
                          {"source_previous", 3, src}});
  if (turbulent_) {
    std::vector<double> k(N), e(N), none(N, 0.0);
    o = 0;
    each_cell([&](const long*, std::size_t n) { k[o] = k_[n], e[o] = eps_[n], ++o; });
    // fv's first guesses of its k and epsilon solves (the last step's change):
    // this solver starts from k and epsilon themselves, so fv restarting from
    // here does too.
    grid::save_cell_fields(comm_, dir + "/fv_turbulence.h5", time_, steps_, {n_[0], n_[1], n_[2]}, box_,
                           {{"k", 1, k}, {"epsilon", 1, e}, {"k_change", 1, none}, {"epsilon_change", 1, none}});
  }
  output::atomic_write(dir + "/fv_clock.txt",
                       fmt::format("{} {:a} {:a} {:a}\n", steps_, time_, dt_prev_, dt_prev2_));
}

void FvReference::load(const std::string& dir, long, double) {
  const std::string path = dir + "/fv.h5";
  const coupler::Index3 cells{n_[0], n_[1], n_[2]};
  const auto u = grid::load_cell_field(path, "velocity_faces", cells, box_, 3);
  const auto top = grid::load_cell_field(path, "velocity_upper", cells, box_, 3);
  const auto old = grid::load_cell_field(path, "velocity_previous", cells, box_, 3);
  const auto adv = grid::load_cell_field(path, "advection_previous", cells, box_, 3);
  const auto p = grid::load_cell_field(path, "pressure", cells, box_, 1);
  const auto phi = grid::load_cell_field(path, "pressure_increment", cells, box_, 1);
  const auto phi_old = grid::load_cell_field(path, "pressure_increment_previous", cells, box_, 1);
  const auto src = grid::load_cell_field(path, "source_previous", cells, box_, 3);
  std::size_t o = 0;
  each_cell([&](const long* x, std::size_t n) {
    for (std::size_t c = 0; c < 3; ++c) {
      u_[c][n] = u[3 * o + c];
      u_old_[c][n] = old[3 * o + c];
      adv_old_[c][n] = adv[3 * o + c];
      source_old_[c][n] = src[3 * o + c];
      const int C = static_cast<int>(c);
      if (C < dims_ && x[C] == n_[C] - 1 && sides_[2 * C + 1].kind == Kind::open)
        u_[c][n + static_cast<std::size_t>(step_of(C))] = top[3 * o + c];
    }
    p_[n] = p[o];
    phi_[n] = phi[o];
    phi_old_[n] = phi_old[o];
    ++o;
  });
  wrap_cells(source_old_);
  std::ifstream clock(dir + "/fv_clock.txt");
  std::string t, dt, dt2;
  if (!(clock >> steps_ >> t >> dt >> dt2))
    throw std::runtime_error(fmt::format("fv-reference: {}/fv_clock.txt is missing or unreadable", dir));
  time_ = std::strtod(t.c_str(), nullptr);
  dt_prev_ = std::strtod(dt.c_str(), nullptr);
  dt_prev2_ = std::strtod(dt2.c_str(), nullptr);
  velocity_ghosts(u_, time_, true, false);
  double face_p[6];
  for (int f = 0; f < 6; ++f) face_p[f] = side_pressure(f, time_);
  pressure_ghosts(p_, face_p);
  if (turbulent_) {
    const auto k = grid::load_cell_field(dir + "/fv_turbulence.h5", "k", cells, box_, 1);
    const auto e = grid::load_cell_field(dir + "/fv_turbulence.h5", "epsilon", cells, box_, 1);
    o = 0;
    each_cell([&](const long*, std::size_t n) { k_[n] = k[o], eps_[n] = e[o], ++o; });
    inlet_time_ = time_;
    scalar_ghosts(k_, inlet(0), log_law_ ? 1.0 : 0.0, true);
    scalar_ghosts(eps_, inlet(1), 1.0, true);
    eddy_viscosity();
    each_cell([&](const long*, std::size_t n) {
      if (!(k_[n] > 0 && eps_[n] > 0 && std::isfinite(nut_[n])))
        throw std::runtime_error(
            fmt::format("fv-reference: {}/fv_turbulence.h5 holds a k or an epsilon that is not positive, or "
                        "a nu_t that is "
                        "not finite: the checkpoint is damaged; restart from another one",
                        dir));
    });
  }
}

}  // namespace coflow::fluid
