// coflow-check: the finite-volume fluid (fv): lid-driven cavity against Ghia,
// Ghia & Shin 1982, Taylor-Green error against the exact decay, divergence
// after the projection, Stokes' oscillating wall.
#include <complex>

#include "../check/check.hpp"
#include "../ghia_1982.hpp"

namespace coflow::check {

namespace {

using validation::kTableI;
using validation::kTableII;

// Component c of the snapshot's cell-centre velocity on the centre line
// across axis `across` (the mid-plane of the other axis), at s in [0, 1] of
// the box: linear between the centres, the wall's value on the walls.
double on_line(const std::vector<double>& u, long nx, long ny, int c, int along, double s, double wall_lo,
               double wall_hi) {
  const long n = along == 1 ? ny : nx, m = along == 1 ? nx : ny;
  auto at = [&](long i) {  // mean of the two cells beside the mid-plane
    const long a = m / 2 - 1, b = m / 2;
    auto cell = [&](long k, long j) {
      const long ix = along == 1 ? k : j, iy = along == 1 ? j : k;
      return u[static_cast<std::size_t>((iy * nx + ix) * 3 + c)];
    };
    return m % 2 == 0 ? 0.5 * (cell(a, i) + cell(b, i)) : cell(m / 2, i);
  };
  const double x = s * n - 0.5;  // in cell-centre units
  if (x <= 0) return wall_lo + (at(0) - wall_lo) * (s * n) / 0.5;
  if (x >= n - 1) return wall_hi + (at(n - 1) - wall_hi) * ((1 - s) * n) / 0.5;
  const long i = static_cast<long>(std::floor(x));
  const double w = x - i;
  return (1 - w) * at(i) + w * at(i + 1);
}

// The last fluid snapshot's time, cell-centre velocity (3 per cell, x
// fastest) and cells along x and y (2D).
struct Velocity {
  double t;
  std::vector<double> u;
  long nx, ny;
};
Velocity last_velocity(const std::string& dir) {
  const std::string snap = last_snapshot(dir);
  std::vector<std::size_t> dims;
  auto u = output::read_dataset(snap, "velocity", &dims);
  return {output::read_time(snap), std::move(u), static_cast<long>(dims[2]), static_cast<long>(dims[1])};
}

}  // namespace

// The lid (y+, velocity U along x) drives a square cavity of side L: the
// centre-line profiles against Ghia's tables for Re = U L / nu (100 or 1000).
int cavity(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const double L = d.upper[0] - d.lower[0], U = fp.boundary(3, cfg).value.values.at(0);
  const double re = U * L / fp.viscosity;
  const bool re100 = std::abs(re - 100) < 1e-6 * 100;
  if (!re100 && std::abs(re - 1000) > 1e-6 * 1000)
    throw std::runtime_error(fmt::format("Re = {:.6g}: Ghia's tables here are for 100 and 1000", re));
  std::vector<std::size_t> dims;
  const auto u = output::read_dataset(last_snapshot(dir), "velocity", &dims);
  const long ny = static_cast<long>(dims[1]), nx = static_cast<long>(dims[2]);
  double du = 0.0, dv = 0.0;
  for (const auto& g : kTableI) {
    const double ref = re100 ? g.re100 : g.re1000;
    du = nan_max(du, std::abs(on_line(u, nx, ny, 0, 1, g.at, 0.0, U) / U - ref));
  }
  for (const auto& g : kTableII) {
    const double ref = re100 ? g.re100 : g.re1000;
    dv = nan_max(dv, std::abs(on_line(u, nx, ny, 1, 0, g.at, 0.0, 0.0) / U - ref));
  }
  std::printf("reynolds=%.6g\nmax_deviation_u=%.6e\nmax_deviation_v=%.6e\nmax_deviation=%.6e\n", re, du, dv,
              nan_max(du, dv));
  return 0;
}

// Stokes' second problem in a gap of depth H (configs/validation/fv_stokes_layer.yaml):
// the wall y- moves as U sin(omega t), T = 2 pi / omega = 1 s, the wall y+ rests.
// The periodic state is Im[U e^{i omega t} sinh(k (H - y)) / sinh(k H)], k =
// (1 + i) / delta, delta = sqrt(2 nu / omega) (the gap's form of Stokes' 1851
// solution: it satisfies u_t = nu u_yy, u(0) = U sin(omega t), u(H) = 0).
// Prints the cells' root-mean-square error over U at the last snapshot
// (l2_error). The check first makes sure the run's wall followed
// sin(2 pi t / 1 s): the reference is for that motion only.
int stokes_layer(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const auto wall = fp.boundary(2, cfg);
  const double U = wall.value.values.at(0), omega = 2 * std::numbers::pi / 1.0;
  if (wall.profile != "expression") throw std::runtime_error("the y- face needs profile: expression");
  for (double tt = 0.0; tt < 1.0; tt += 0.0625) {
    const double s[3] = {0.5, 0.0, 0.5};
    if (std::abs(wall.profile_factor(2, s, cfg, tt) - std::sin(omega * tt)) > 1e-12)
      throw std::runtime_error(
          "the y- face's profile_expression is not sin(2*pi*t/1.0): the check's reference "
          "is for that motion");
  }
  const auto h = d.spacing();
  const auto [t, u, nx, ny] = last_velocity(dir);
  // fv's moving wall is the face y = 0; lbm's Zou-He face moves the centres
  // of the first cells, y = h/2 (its resting wall, half-way bounce-back, is
  // at y = H for both).
  const double y0 = cfg.component("fluid").variant.rfind("lbm", 0) == 0 ? 0.5 * h[1] : 0.0;
  const double H = d.upper[1] - d.lower[1] - y0, delta = std::sqrt(2 * fp.viscosity / omega);
  const std::complex<double> k(1.0 / delta, 1.0 / delta),
      phase = std::exp(std::complex<double>(0.0, omega * t));
  double e2 = 0.0;
  for (long j = 0; j < ny; ++j)
    for (long i = 0; i < nx; ++i) {
      const double y = (j + 0.5) * h[1] - y0;
      const double ua = U * (phase * std::sinh(k * (H - y)) / std::sinh(k * H)).imag();
      const double un = u[static_cast<std::size_t>((j * nx + i) * 3)];
      e2 += (un - ua) * (un - ua);
    }
  std::printf("l2_error=%.6e\n", std::sqrt(e2 / static_cast<double>(nx * ny)) / U);
  return 0;
}

// The 2D Taylor-Green vortex of fluid.initial at the last snapshot: relative
// L2 error of the cell-centre velocity against the exact decay (the analytic
// fluid's formula).
int tg_error(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const auto h = d.spacing();
  const auto [t, u, nx, ny] = last_velocity(dir);
  const double kx = 2 * std::numbers::pi / (d.upper[0] - d.lower[0]),
               ky = 2 * std::numbers::pi / (d.upper[1] - d.lower[1]);
  const double decay = std::exp(-fp.viscosity * (kx * kx + ky * ky) * t), U = fp.initial_amplitude;
  double e2 = 0.0, r2 = 0.0;
  for (long j = 0; j < ny; ++j)
    for (long i = 0; i < nx; ++i) {
      const double X = kx * (i + 0.5) * h[0], Y = ky * (j + 0.5) * h[1];
      const double ua = U * std::sin(X) * std::cos(Y) * decay,
                   va = -U * (kx / ky) * std::cos(X) * std::sin(Y) * decay;
      const double un = u[static_cast<std::size_t>((j * nx + i) * 3)],
                   vn = u[static_cast<std::size_t>((j * nx + i) * 3 + 1)];
      e2 += (un - ua) * (un - ua) + (vn - va) * (vn - va);
      r2 += ua * ua + va * va;
    }
  std::printf("l2_error=%.6e\n", std::sqrt(e2 / r2));
  return 0;
}

// The shielded vortex of fluid.initial (field: vortex) carried by the
// uniform initial velocity U across a periodic box, at the last snapshot,
// against the exact solution: an axisymmetric vortex's vorticity diffuses by
// the heat equation (the advection term vanishes), so its stream function
// psi = A R e^(1/2) exp(-r^2 / (2 R^2)) becomes A R e^(1/2) (R^2 / s^2)
// exp(-r^2 / (2 s^2)), s^2 = R^2 + 2 nu t, centred at x0 + U t (Galilean
// invariance; the periodic images' share is below 1e-40 here). Prints the
// L2 (root mean square) and largest velocity errors relative to the initial
// peak swirl A, and with refinement (series/fluid.csv's cells) the mean
// cells over the run as a fraction of the uniform grid's.
int vortex(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const auto h = d.spacing();
  const auto [t, u, nx, ny] = last_velocity(dir);
  const double A = fp.initial_amplitude, R = fp.initial_radius, s2 = R * R + 2 * fp.viscosity * t;
  const double L[2] = {d.upper[0] - d.lower[0], d.upper[1] - d.lower[1]};
  double centre[2], e2 = 0.0, worst = 0.0;
  for (int a = 0; a < 2; ++a)
    centre[a] = d.lower[a] + std::fmod(fp.initial_center.values.at(static_cast<std::size_t>(a)) - d.lower[a] +
                                           fp.initial_velocity[static_cast<std::size_t>(a)] * t, L[a]);
  for (long j = 0; j < ny; ++j)
    for (long i = 0; i < nx; ++i) {
      double r[2] = {d.lower[0] + (i + 0.5) * h[0] - centre[0], d.lower[1] + (j + 0.5) * h[1] - centre[1]};
      for (int a = 0; a < 2; ++a) r[a] -= L[a] * std::round(r[a] / L[a]);  // the nearest image
      const double w = A * R * std::exp(0.5) * (R * R / s2) / s2 * std::exp(-(r[0] * r[0] + r[1] * r[1]) / (2 * s2));
      const double du = u[static_cast<std::size_t>((j * nx + i) * 3)] - (fp.initial_velocity[0] - w * r[1]);
      const double dv = u[static_cast<std::size_t>((j * nx + i) * 3 + 1)] - (fp.initial_velocity[1] + w * r[0]);
      const double e = du * du + dv * dv;
      e2 += e;
      worst = std::isnan(e) ? HUGE_VAL : std::max(worst, std::sqrt(e));
    }
  std::printf("time=%.6g\nl2_error=%.6e\nmax_error=%.6e\n", t, std::sqrt(e2 / static_cast<double>(nx * ny)) / A,
              worst / A);
  const LastRow last(dir + "/series/fluid.csv");
  if (!last.has("cells")) return 0;  // the uniform grid
  double cells = 0.0;
  const auto rows = read_series(dir + "/series/fluid.csv");
  for (const auto& row : rows) cells += row.at(last.column("cells"));
  std::printf("cells_fraction=%.6e\n", cells / static_cast<double>(rows.size()) / static_cast<double>(nx * ny));
  return 0;
}

// The largest divergence after the projection (series/fluid.csv's
// max_divergence, last window) in units of U / dx, U the largest velocity.
int divergence(const std::string& dir) {
  const auto cfg = load(dir);
  const LastRow last(dir + "/series/fluid.csv");
  const double dx = cfg.domain.spacing()[0];
  const double U = std::max(last("max_velocity"), 1e-300);
  std::printf("divergence_per_u_dx=%.6e\npoisson_iterations=%g\n", last("max_divergence") * dx / U,
              last("poisson_iterations"));
  return 0;
}

// A disturbance carried out through an open face: run A in the box, run B in
// a box longer downstream on the same grid (the reference, its face far
// away), snapshots at the same times. Prints the largest |u_A - u_B| over the
// upstream 80 % of A's cells at any snapshot (what the face sends back
// upstream) and over all of A's cells at the last (what stays after the
// disturbance left), relative to the initial vortex's peak swirl.
int outflow_reflection(const std::string& a, const std::string& b) {
  const auto cfg = load(a);
  const double swirl = fluid_params(cfg).initial_amplitude;
  const auto sa = snapshots(a, "fluid"), sb = snapshots(b, "fluid");
  if (sa.size() != sb.size()) throw std::runtime_error("the two runs wrote different numbers of snapshots");
  double reflection = 0.0, residual = 0.0;
  for (std::size_t i = 0; i < sa.size(); ++i) {
    std::vector<std::size_t> da, db;
    const auto ua = output::read_dataset(a + "/fluid/" + output::snapshot_name(sa[i].first), "velocity", &da);
    const auto ub = output::read_dataset(b + "/fluid/" + output::snapshot_name(sb[i].first), "velocity", &db);
    if (std::abs(sa[i].second - sb[i].second) > 1e-9 * std::max(1.0, sa[i].second))
      throw std::runtime_error("the snapshots' times differ");
    const long ny = static_cast<long>(da[1]), nxa = static_cast<long>(da[2]), nxb = static_cast<long>(db[2]);
    const long upstream = nxa * 4 / 5;
    for (long j = 0; j < ny; ++j)
      for (long x = 0; x < nxa; ++x)
        for (long c = 0; c < 3; ++c) {
          const double d = std::abs(ua[static_cast<std::size_t>((j * nxa + x) * 3 + c)] -
                                    ub[static_cast<std::size_t>((j * nxb + x) * 3 + c)]) /
                           swirl;
          if (!(d == d)) throw std::runtime_error("a velocity is not a number");
          if (x < upstream) reflection = nan_max(reflection, d);
          if (i + 1 == sa.size()) residual = nan_max(residual, d);
        }
  }
  std::printf("reflection=%.4e\nresidual=%.4e\n", reflection, residual);
  return 0;
}

}  // namespace coflow::check
