// fv-reference: k-epsilon with the two-layer wall model, fv's
// fluid/fv/turbulence/ written plainly (the oracle for it): the same
// advection sub-steps, implicit diffusion with linearised sinks, fixed
// epsilon in the one-equation layer and eddy viscosity, with loops over the
// whole grid and conjugate gradients on operators applied cell by cell.
#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "fluid/fv/turbulence/closure.hpp"
#include "fluid/fv_reference/fv_reference.hpp"

namespace coflow::fluid {

bool FvReference::is_inlet(int face) const {
  return sides_[face].kind == Kind::wall && sides_[face].velocity[face / 2] != 0.0;
}

void FvReference::turbulence_init() {
  turbulent_ = fluid_.turbulence.on;
  if (!turbulent_) return;
  turb_ = fluid_.turbulence;
  log_law_ = turb_.wall == "log-law";
  inlets_ = fluid_.inlet_turbulence(cfg_);
  inlet_time_ = time_;
  const std::size_t size = u_[0].size();
  k_.assign(size, turb_.initial_k);
  eps_.assign(size, turb_.initial_epsilon);
  nut_.assign(size, 0.0);
  wall_y_.assign(size, std::numeric_limits<double>::infinity());
  const fv::Closure cl{turb_.constants, nu_, turb_.wall == "two-layer"};
  for (long k = -g_[2]; k < n_[2] + g_[2]; ++k)
    for (long j = -g_[1]; j < n_[1] + g_[1]; ++j)
      for (long i = -g_[0]; i < n_[0] + g_[0]; ++i) {
        const long x[3] = {i, j, k};
        const auto n = static_cast<std::size_t>(at(x));
        for (int f = 0; f < 2 * dims_; ++f) {
          if (sides_[f].kind != Kind::wall || is_inlet(f)) continue;
          const double c = static_cast<double>(x[f / 2]) + 0.5;
          wall_y_[n] = std::min(wall_y_[n], (f % 2 == 0 ? c : static_cast<double>(n_[f / 2]) - c) * h_[f / 2]);
        }
        if (cl.one_equation(wall_y_[n], k_[n])) eps_[n] = cl.epsilon_near_wall(wall_y_[n], k_[n]);
      }
  box_wall_y_ = wall_y_;
  std::vector<char> fixed(k_.size(), 0);
  if (log_law_) wall_function_epsilon(fixed);
  scalar_ghosts(k_, inlet(0), log_law_ ? 1.0 : 0.0, true);
  scalar_ghosts(eps_, inlet(1), 1.0, true);
  eddy_viscosity();
}

// k (q 0), epsilon (1) or nu_t (2) entering through `face` beside the cell x
// at inlet_time_: the face's values, or from its tables at the cell's centre
// on the face, or from its intensity and the inlet's speed there (the
// face's velocity, ramp and profile factor).
double FvReference::inlet_value(int q, int face, const long* x) const {
  const int a = face / 2;
  double speed = 0.0;
  if (inlets_.from_speed(face)) {
    const Vec3 U = side_velocity(face, inlet_time_);
    const double w = dims_ == 3 ? U[2] : 0.0;  // in 2D the flow has no z component
    long on[3] = {x[0], x[1], x[2]};
    on[a] = 0;  // the profile's place along the face's axis is not read (fv's lines pass 0 there too)
    speed = std::sqrt(U[0] * U[0] + U[1] * U[1] + w * w) * std::abs(profile(face, a, on, inlet_time_));
  }
  const auto& d = cfg_.domain;
  double p[3];  // the cell's centre on the face, m
  for (int e = 0; e < 3; ++e) p[e] = d.lower[e] + (static_cast<double>(x[e]) + 0.5) * h_[e];
  p[a] = face % 2 == 0 ? d.lower[a] : d.upper[a];
  const auto in = inlets_.at(face, speed, p);
  const double k = in[0], eps = in[1];
  if (q == 0) return k;
  if (q == 1) return eps;
  const fv::Closure cl{turb_.constants, nu_, turb_.wall == "two-layer"};
  return k > 0.0 ? cl.nu_t(std::numeric_limits<double>::infinity(), k, eps) : 0.0;
}

// fv's fill_scalar_ghosts: periodic copies; beyond a wall wall_sign times the
// mirrored cell; beyond a symmetry face the mirrored cell; beyond an inlet or
// an open face the inlet's value or the mirrored cell, or with `extrapolate`
// the lines through the inlet's value or the last two cells, not below zero.
void FvReference::scalar_ghosts(Field& q, const FaceValues& inlets, double wall_sign,
                                bool extrapolate) const {
  for (int a = 0; a < dims_; ++a) {
    const long n = n_[a], s = step_of(a);
    for_lines(a, [&](long o, const long* line) {
      auto Q = [&](long m) -> double& { return q[static_cast<std::size_t>(o + m * s)]; };
      if (sides_[2 * a].kind == Kind::periodic) {
        Q(-1) = Q(n - 1), Q(-2) = Q(n - 2), Q(n) = Q(0), Q(n + 1) = Q(1);
        return;
      }
      for (int side = 0; side < 2; ++side) {
        const int face = 2 * a + side;
        const double inlet = is_inlet(face) ? inlets(face, line) : 0.0;
        const long q0 = side == 0 ? 0 : n - 1, in = side == 0 ? 1 : -1;  // first cell, inwards
        const double v0 = Q(q0), v1 = Q(q0 + in);
        double g1 = v0, g2 = v1;
        const bool wall = sides_[face].kind == Kind::wall && !is_inlet(face);
        if (wall) g1 = wall_sign * v0, g2 = wall_sign * v1;
        if (is_inlet(face)) {
          g1 = extrapolate ? std::max(0.0, 2 * inlet - v0) : inlet;
          g2 = extrapolate ? std::max(0.0, 2 * inlet - v1) : inlet;
        }
        if (extrapolate && sides_[face].kind == Kind::open)
          g1 = std::max(0.0, 2 * v0 - v1), g2 = std::max(0.0, 3 * v0 - 2 * v1);
        Q(q0 - in) = g1;
        Q(q0 - 2 * in) = g2;
      }
    });
  }
}

void FvReference::eddy_viscosity() {
  const fv::Closure cl{turb_.constants, nu_, turb_.wall == "two-layer"};
  each_cell([&](const long*, std::size_t n) { nut_[n] = cl.nu_t(wall_y_[n], k_[n], eps_[n]); });
  scalar_ghosts(nut_, inlet(2), -1.0, false);  // the inlet's nu_t beyond each inlet face
  if (!log_law_) return;
  // The wall functions: nu_t beyond a wall such that the wall face's nu + nu_t is nu_w.
  const fv::WallFunction wf{turb_.constants, nu_};
  for (int f = 0; f < 2 * dims_; ++f) {
    if (sides_[f].kind != Kind::wall || is_inlet(f)) continue;
    const int a = f / 2;
    const long s = step_of(a), first = f % 2 == 0 ? 0 : n_[a] - 1, out = f % 2 == 0 ? -1 : 1;
    for_lines(a, [&](long o, const long*) {
      const auto in = static_cast<std::size_t>(o + first * s);
      const double g = 2.0 * (wf.nu_wall(0.5 * h_[a], std::max(k_[in], 0.0)) - nu_) - nut_[in];
      nut_[static_cast<std::size_t>(o + (first + out) * s)] = g;
      nut_[static_cast<std::size_t>(o + (first + 2 * out) * s)] = g;
    });
  }
}

template <class F>
void FvReference::for_wall_cells(F&& f) const {
  for (int face = 0; face < 2 * dims_; ++face) {
    if (sides_[face].kind != Kind::wall || is_inlet(face)) continue;
    const int a = face / 2;
    each_cell([&](const long* x, std::size_t n) {
      if (x[a] == (face % 2 == 0 ? 0 : n_[a] - 1)) f(face, x, n);
    });
  }
}

double FvReference::wall_speed(int face, const long* x, std::size_t n, double t) const {
  double s2 = 0.0;
  for (int c = 0; c < dims_; ++c) {
    if (c == face / 2) continue;
    const Field& q = u_[static_cast<std::size_t>(c)];
    const double U = side_velocity(face, t)[c] * profile(face, c, x, t);
    const double u = 0.5 * (q[n] + q[n + static_cast<std::size_t>(step_of(c))]) - U;
    s2 += u * u;
  }
  return std::sqrt(s2);
}

// epsilon in the cells next to walls: the wall function's (the larger of two
// walls'), fixed.
void FvReference::wall_function_epsilon(std::vector<char>& fixed) {
  const fv::WallFunction wf{turb_.constants, nu_};
  for_wall_cells([&](int f, const long*, std::size_t n) {
    const double e = wf.epsilon(0.5 * h_[f / 2], std::max(k_[n], 0.0));
    eps_[n] = fixed[n] ? std::max(eps_[n], e) : e;
    fixed[n] = 1;
  });
}

double FvReference::nu_at(int c, long n, int d, int side) const {
  if (!turbulent_) return nu_;
  auto T = [&](long m) { return nut_[static_cast<std::size_t>(m)]; };
  const long sc = step_of(c);
  if (d == c) return nu_ + T(side == 0 ? n - sc : n);
  const long e = side == 0 ? -step_of(d) : step_of(d);
  return nu_ + 0.25 * (T(n) + T(n - sc) + T(n + e) + T(n + e - sc));
}

double FvReference::viscous_at(const Field& q, int c, long n) const {
  auto Q = [&](long m) { return q[static_cast<std::size_t>(m)]; };
  double l = 0.0;
  for (int d = 0; d < dims_; ++d) {
    const long s = step_of(d);
    l += (nu_at(c, n, d, 1) * (Q(n + s) - Q(n)) - nu_at(c, n, d, 0) * (Q(n) - Q(n - s))) / (h_[d] * h_[d]);
  }
  return l;
}

// d/dx_d (nu_t d u_d / dx_c) at u_c's face n (fv's eddy_viscosity.cpp).
double FvReference::stress_transpose_at(const Faces& u, int c, long n) const {
  auto T = [&](long m) { return nut_[static_cast<std::size_t>(m)]; };
  const long sc = step_of(c);
  double r = 0.0;
  for (int d = 0; d < dims_; ++d) {
    auto V = [&](long m) { return u[static_cast<std::size_t>(d)][static_cast<std::size_t>(m)]; };
    const long sd = step_of(d);
    if (d == c) {
      r += (T(n) * (V(n + sc) - V(n)) - T(n - sc) * (V(n) - V(n - sc))) / (h_[c] * h_[c]);
      continue;
    }
    const double up = 0.25 * (T(n) + T(n - sc) + T(n + sd) + T(n + sd - sc)) * (V(n + sd) - V(n + sd - sc));
    const double dn = 0.25 * (T(n) + T(n - sc) + T(n - sd) + T(n - sd - sc)) * (V(n) - V(n - sc));
    r += (up - dn) / (h_[c] * h_[d]);
  }
  return r;
}

double FvReference::strain_rate2_at(long n) const {
  double g[3][3] = {};
  for (int c = 0; c < dims_; ++c) {
    auto Q = [&](long m) { return u_[static_cast<std::size_t>(c)][static_cast<std::size_t>(m)]; };
    const long sc = step_of(c);
    for (int d = 0; d < dims_; ++d) {
      const long sd = step_of(d);
      g[c][d] = d == c ? (Q(n + sc) - Q(n)) / h_[c]
                       : 0.25 * ((Q(n + sd) + Q(n + sd + sc)) - (Q(n - sd) + Q(n - sd + sc))) / h_[d];
    }
  }
  double s2 = 0.0;
  for (int c = 0; c < dims_; ++c) {
    s2 += 2.0 * g[c][c] * g[c][c];
    for (int d = c + 1; d < dims_; ++d) s2 += (g[c][d] + g[d][c]) * (g[c][d] + g[d][c]);
  }
  return s2;
}

// q <- q - dt (u . grad) q in sub-steps of Courant number <= 1/2, the inlet's
// value on its face.
void FvReference::advect_scalar(Field& q, const FaceValues& inlet, double wall_sign, double dt) const {
  double rate = 0.0;
  for (int d = 0; d < dims_; ++d) {
    double m = 0.0;
    each_cell([&](const long*, std::size_t n) {
      const Field& v = u_[static_cast<std::size_t>(d)];
      m = std::max({m, std::abs(v[n]), std::abs(v[n + static_cast<std::size_t>(step_of(d))])});
    });
    rate += m / h_[d];
  }
  const int sub = std::max(1, static_cast<int>(std::ceil(2.0 * rate * dt * (1 - 1e-12))));
  Field next = q;
  for (int step = 0; step < sub; ++step) {
    each_cell([&](const long* x, std::size_t n) {
      auto Q = [&](long m) { return q[static_cast<std::size_t>(static_cast<long>(n) + m)]; };
      double r = 0.0;
      for (int d = 0; d < dims_; ++d) {
        const long s = step_of(d);
        const Field& v = u_[static_cast<std::size_t>(d)];
        const double up = v[n + static_cast<std::size_t>(s)], um = v[n];
        double qp = fv::face_value(true, Q(-s), Q(0), Q(s), Q(2 * s), up);
        double qm = fv::face_value(true, Q(-2 * s), Q(-s), Q(0), Q(s), um);
        if (x[d] == n_[d] - 1 && is_inlet(2 * d + 1)) qp = inlet(2 * d + 1, x);
        if (x[d] == 0 && is_inlet(2 * d)) qm = inlet(2 * d, x);
        r -= (up * qp - um * qm - Q(0) * (up - um)) / h_[d];
      }
      next[n] = Q(0) + dt / sub * r;
    });
    q.swap(next);
    scalar_ghosts(q, inlet, wall_sign, true);
  }
}

// (1/dt + sink) q' - div((nu + nu_t / sigma) grad q') = q / dt + source, q' =
// 0 beyond walls (wall_zero) or no flux there, q' = inlet beyond inlets, the
// cells marked in `fixed` keeping their values.
void FvReference::solve_scalar(Field& q, const Field& sink, const Field& source, double sigma,
                               const FaceValues& inlet, bool wall_zero, const std::vector<char>* fixed,
                               double dt, const char* what) const {
  std::vector<long> rows;
  Field rhs(q.size(), 0.0);
  each_cell([&](const long*, std::size_t n) {
    if (fixed && (*fixed)[n]) return;
    rows.push_back(static_cast<long>(n));
    rhs[n] = q[n] / dt + source[n];
  });
  auto apply = [&](const Field& xf, Field& y, bool zero) {
    Field X(q.size(), 0.0);
    each_cell([&](const long*, std::size_t n) { X[n] = fixed && (*fixed)[n] ? (zero ? 0.0 : q[n]) : xf[n]; });
    scalar_ghosts(
        X, [](int, const long*) { return 0.0; }, 0.0,
        false);  // periodic copies (the boundary ghosts are not read)
    for (long i : rows) {
      const auto I = static_cast<std::size_t>(i);
      double v = (1.0 / dt + sink[I]) * X[I];
      const long x[3] = {i % m_[0] - g_[0], (i / m_[0]) % m_[1] - g_[1], i / (m_[0] * m_[1]) - g_[2]};
      for (int d = 0; d < dims_; ++d)
        for (int side = 0; side < 2; ++side) {
          const long nb = i + (side == 0 ? -step_of(d) : step_of(d));
          const auto NB = static_cast<std::size_t>(nb);
          const double D = (nu_ + 0.5 * (nut_[I] + nut_[NB]) / sigma) / (h_[d] * h_[d]);
          const int face = 2 * d + side;
          if (sides_[face].kind != Kind::periodic && x[d] == (side == 0 ? 0 : n_[d] - 1)) {
            if (is_inlet(face))
              v += 2 * D * (X[I] - (zero ? 0.0 : inlet(face, x)));
            else if (sides_[face].kind == Kind::wall && wall_zero) v += 2 * nu_ / (h_[d] * h_[d]) * X[I];
            continue;
          }
          v += D * (X[I] - X[NB]);
        }
      y[I] = v;
    }
  };
  Field zero(q.size(), 0.0), affine(q.size(), 0.0);
  apply(zero, affine, false);
  for (long i : rows) rhs[static_cast<std::size_t>(i)] -= affine[static_cast<std::size_t>(i)];
  Field x = q;
  conjugate_gradients([&](const Field& a, Field& y) { apply(a, y, true); }, rows, x, rhs, what);
  for (long i : rows) q[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)];
}

void FvReference::turbulence_step(double dt) {
  const fv::Closure cl{turb_.constants, nu_, turb_.wall == "two-layer"};
  const auto& c = turb_.constants;
  inlet_time_ = next_time_;  // the velocity's faces at the new time
  Field production(k_.size(), 0.0), sink_k(k_.size(), 0.0), sink_e(k_.size(), 0.0), source_e(k_.size(), 0.0);
  each_cell([&](const long*, std::size_t n) {
    const fv::Sources q = fv::sources(c, nut_[n], strain_rate2_at(static_cast<long>(n)), k_[n], eps_[n]);
    production[n] = q.production, sink_k[n] = q.sink_k, sink_e[n] = q.sink_epsilon, source_e[n] = q.source_epsilon;
  });
  if (log_law_) {  // the wall functions' production, summed over a cell's walls
    const fv::WallFunction wf{turb_.constants, nu_};
    for_wall_cells([&](int, const long*, std::size_t n) { production[n] = 0.0; });
    for_wall_cells([&](int f, const long* x, std::size_t n) {
      production[n] += wf.production(0.5 * h_[f / 2], k_[n], wall_speed(f, x, n, next_time_));
    });
  }
  const double k_wall = log_law_ ? 1.0 : 0.0;  // beyond a wall: 0, or mirrored (no flux)
  advect_scalar(k_, inlet(0), k_wall, dt);
  advect_scalar(eps_, inlet(1), 1.0, dt);
  solve_scalar(k_, sink_k, production, c.sigma_k, inlet(0), !log_law_, nullptr, dt, "k solve");
  scalar_ghosts(k_, inlet(0), k_wall, true);
  std::vector<char> fixed(k_.size(), 0);
  if (log_law_) wall_function_epsilon(fixed);
  if (cl.two_layer)
    for (std::size_t n = 0; n < k_.size(); ++n)
      if (cl.one_equation(wall_y_[n], k_[n])) {
        fixed[n] = 1;
        eps_[n] = cl.epsilon_near_wall(wall_y_[n], k_[n]);
      }
  solve_scalar(eps_, sink_e, source_e, c.sigma_epsilon, inlet(1), false, &fixed, dt, "epsilon solve");
  scalar_ghosts(eps_, inlet(1), 1.0, true);
  each_cell([&](const long*, std::size_t n) {
    if (!(k_[n] > 0 && eps_[n] > 0))
      throw std::runtime_error(fmt::format("fv-reference: k-epsilon lost positivity at t = {:.6g} s", next_time_));
  });
  eddy_viscosity();
}

// y+ at the centres of the cells next to walls, the largest of a corner
// cell's walls' (fv's eddy_viscosity.cpp).
std::vector<double> FvReference::y_plus() const {
  std::vector<double> out(static_cast<std::size_t>(n_[0] * n_[1] * n_[2]), 0.0);
  if (!turbulent_) return out;
  for (int f = 0; f < 2 * dims_; ++f) {
    if (sides_[f].kind != Kind::wall || is_inlet(f)) continue;
    const int a = f / 2;
    const long in = f % 2 == 0 ? step_of(a) : -step_of(a);
    std::size_t o = 0;
    const fv::WallFunction wf{turb_.constants, nu_};
    each_cell([&](const long* x, std::size_t n) {
      if (x[a] == (f % 2 == 0 ? 0 : n_[a] - 1) && log_law_) {  // u_tau from the wall functions' shear
        const double y = 0.5 * h_[a];
        fv::keep_largest(out[o], y * std::sqrt(wf.nu_wall(y, k_[n]) * wall_speed(f, x, n, time_) / y) / nu_);
      } else if (x[a] == (f % 2 == 0 ? 0 : n_[a] - 1)) {
        double shear2 = 0.0;
        for (int c = 0; c < dims_; ++c) {
          if (c == a) continue;
          const Field& q = u_[static_cast<std::size_t>(c)];
          const auto sc = static_cast<std::size_t>(step_of(c)), I = static_cast<std::size_t>(static_cast<long>(n) + in);
          const double U = side_velocity(f, time_)[c] * profile(f, c, x, time_);  // the wall's own velocity there
          const double u0 = 0.5 * (q[n] + q[n + sc]) - U, u1 = 0.5 * (q[I] + q[I + sc]) - U;
          const double slope = (9 * u0 - u1) / (3 * h_[a]);
          shear2 += slope * slope;
        }
        fv::keep_largest(out[o], 0.5 * h_[a] * std::sqrt(nu_ * std::sqrt(shear2)) / nu_);
      }
      ++o;
    });
  }
  return out;
}

}  // namespace coflow::fluid
