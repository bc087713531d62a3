#include "fluid/analytic/analytic_fluid.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

namespace coflow::fluid {

AnalyticFluid::AnalyticFluid(const Setup& s, const Params& p)
    : cfg_(s.cfg), fluid_(s.params), p_(p), comm_(s.comm), owned_(s.decomposition.block(s.rank)) {
  const std::size_t n = owned_.volume();
  u_.resize(3 * n);
  p_field_.resize(n);
  omega_.resize(3 * n);
  k_.resize(n);
  eps_.resize(n);
  rho_.assign(n, fluid_.density);
  evaluate();
}


namespace {

// The 2D Taylor-Green vortex in x-y with the box as period: wave numbers, phases
// at x, and the velocity's decay factor exp(-nu (kx^2 + ky^2) t).
struct TaylorGreen {
  double kx, ky, X, Y, decay;
  static TaylorGreen at(const config::DomainParams& d, const Vec3& x, double nu, double t) {
    const double kx = 2 * std::numbers::pi / (d.upper[0] - d.lower[0]);
    const double ky = 2 * std::numbers::pi / (d.upper[1] - d.lower[1]);
    return {kx, ky, kx * (x[0] - d.lower[0]), ky * (x[1] - d.lower[1]), std::exp(-nu * (kx * kx + ky * ky) * t)};
  }
};

}  // namespace

Vec3 AnalyticFluid::velocity_at(const Vec3& x, double t) const {
  const auto& d = cfg_.domain;
  if (p_.field == "uniform") return p_.velocity;
  if (p_.field == "grid-turbulence") {
    Vec3 u{0, 0, 0};
    u[p_.flow_axis] = p_.mean_velocity;
    return u;
  }
  if (p_.field == "poiseuille") {
    // u = U (1 - (2 y' / H - 1)^2), walls at the domain faces of wall_axis.
    const double H = d.upper[p_.wall_axis] - d.lower[p_.wall_axis];
    const double s = 2.0 * (x[p_.wall_axis] - d.lower[p_.wall_axis]) / H - 1.0;
    Vec3 u{0, 0, 0};
    u[p_.flow_axis] = p_.max_velocity * (1.0 - s * s);
    return u;
  }
  if (p_.field == "taylor-green") {
    // 2D Taylor-Green vortex in x-y, period = the box; decays as exp(-2 nu k^2 t)
    // for a square box (k = 2 pi / L).
    const auto [kx, ky, X, Y, decay] = TaylorGreen::at(d, x, fluid_.viscosity, t);
    return {p_.max_velocity * std::sin(X) * std::cos(Y) * decay,
            -p_.max_velocity * (kx / ky) * std::cos(X) * std::sin(Y) * decay, 0.0};
  }
  return {0, 0, 0};
}

Vec3 AnalyticFluid::vorticity_at(const Vec3& x, double t) const {
  const auto& d = cfg_.domain;
  Vec3 w{0, 0, 0};
  if (p_.field == "poiseuille") {
    // omega = grad(u_f) x e_f = du_f/dx_w (e_w x e_f); du_f/dx_w = -4 U s / H.
    const int f = p_.flow_axis, n = p_.wall_axis, c = 3 - f - n;
    const double H = d.upper[n] - d.lower[n];
    const double s = 2.0 * (x[n] - d.lower[n]) / H - 1.0;
    const double sign = ((n + 1) % 3 == f) ? 1.0 : -1.0;  // e_n x e_f = +e_c when (n, f, c) is cyclic
    w[c] = sign * (-4.0 * p_.max_velocity * s / H);
    return w;
  }
  if (p_.field == "taylor-green") {
    const auto [kx, ky, X, Y, decay] = TaylorGreen::at(d, x, fluid_.viscosity, t);
    // omega_z = dv/dx - du/dy = U0 (kx^2/ky + ky) sin X sin Y.
    w[2] = p_.max_velocity * (kx * kx / ky + ky) * std::sin(X) * std::sin(Y) * decay;
  }
  return w;
}

double AnalyticFluid::k_at(const Vec3& x) const {
  if (p_.field == "uniform") return p_.k;
  if (p_.field != "grid-turbulence") return 0.0;
  const GridDecay g{p_.mean_velocity, p_.mesh_size};
  return g.k((x[p_.flow_axis] - p_.grid_position) / p_.mesh_size);
}

double AnalyticFluid::epsilon_at(const Vec3& x) const {
  // seed 003 eq. 5.23: epsilon = -U dk/dx (frozen turbulence advected by the mean flow).
  if (p_.field == "uniform") return p_.epsilon;
  if (p_.field != "grid-turbulence") return 0.0;
  const GridDecay g{p_.mean_velocity, p_.mesh_size};
  return -p_.mean_velocity * g.dk_dx((x[p_.flow_axis] - p_.grid_position) / p_.mesh_size);
}

double AnalyticFluid::pressure_at(const Vec3& x, double t) const {
  const auto& d = cfg_.domain;
  if (p_.field == "taylor-green") {
    const auto [kx, ky, X, Y, u_decay] = TaylorGreen::at(d, x, fluid_.viscosity, t);
    const double decay = u_decay * u_decay;  // pressure decays at twice the rate
    const double U = p_.max_velocity;
    return fluid_.initial_pressure +
           0.25 * fluid_.density * U * U * (std::cos(2 * X) + (kx * kx) / (ky * ky) * std::cos(2 * Y)) * decay;
  }
  return fluid_.initial_pressure;
}

void AnalyticFluid::evaluate() {
  const auto& d = cfg_.domain;
  const auto h = d.spacing();
  std::size_t n = 0;
  for (long k = owned_.lo[2]; k < owned_.hi[2]; ++k)
    for (long j = owned_.lo[1]; j < owned_.hi[1]; ++j)
      for (long i = owned_.lo[0]; i < owned_.hi[0]; ++i, ++n) {
        const Vec3 x{d.lower[0] + (i + 0.5) * h[0], d.lower[1] + (j + 0.5) * h[1], d.lower[2] + (k + 0.5) * h[2]};
        const Vec3 u = velocity_at(x, time_);
        const Vec3 w = vorticity_at(x, time_);
        for (int c = 0; c < 3; ++c) {
          u_[3 * n + c] = u[c];
          omega_[3 * n + c] = w[c];
        }
        p_field_[n] = pressure_at(x, time_);
        k_[n] = k_at(x);
        eps_[n] = epsilon_at(x);
      }
}

// The time is the steps times the window (every step is one window), not a
// running sum: a restart sets it the same way (load), so that it has the
// same bits as the run it goes on from (ten sums of 0.1 are 0.9999999999999999).
void AnalyticFluid::advance(double dt) {
  ++steps_;
  time_ = static_cast<double>(steps_) * dt;
  evaluate();
}

std::vector<output::GridField> AnalyticFluid::fields(const config::StringList& names) {
  std::vector<output::GridField> f;
  for (const auto& n : names) {
    if (n == "velocity") f.push_back({n, 3, u_});
    if (n == "pressure") f.push_back({n, 1, p_field_});
    if (n == "density") f.push_back({n, 1, rho_});
    if (n == "vorticity") f.push_back({n, 3, omega_});
    if (n == "k") f.push_back({n, 1, k_});
    if (n == "epsilon") f.push_back({n, 1, eps_});
  }
  return f;
}

Diagnostics AnalyticFluid::diagnostics() {
  const auto h = cfg_.domain.spacing();
  const double vol = h[0] * h[1] * h[2];
  double local[6] = {0, 0, 0, 0, 0, 0}, umax = 0;
  const std::size_t n = owned_.volume();
  for (std::size_t i = 0; i < n; ++i) {
    const double m = fluid_.density * vol;
    double u2 = 0;
    for (int c = 0; c < 3; ++c) {
      local[1 + c] += m * u_[3 * i + c];
      u2 += u_[3 * i + c] * u_[3 * i + c];
    }
    local[0] += m;
    local[4] += 0.5 * m * u2;
    umax = std::max(umax, std::sqrt(u2));
  }
  double global[6], gmax = 0;
  MPI_Allreduce(local, global, 5, MPI_DOUBLE, MPI_SUM, comm_);
  MPI_Allreduce(&umax, &gmax, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return Diagnostics{global[0], {global[1], global[2], global[3]}, global[4], gmax, 0.0, {}};
}

}  // namespace coflow::fluid
