// coflow-check: metrics of a finished run against analytic solutions, printed
// as `name=value` lines for tests/validation/validate.sh.
//
//   coflow-check profile RUN_DIR   steady channel/duct/Couette profile: l2_error
//   coflow-check decay RUN_DIR     Taylor-Green energy decay rate: decay_rate_error
//   coflow-check mass RUN_DIR      relative mass drift over the run: mass_drift
//   coflow-check compare RUN_A RUN_B   last snapshots: max_difference (relative)
//   coflow-check impact RUN_DIR    two-sphere impact: duration_error, restitution, energy_error
//   coflow-check pour RUN_DIR      gravity pour: kinetic_energy_ratio, packing_fraction
//
// The physical parameters come from the run's resolved config.yaml.
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "coflow/catalog.hpp"
#include "coflow/output.hpp"
#include "coflow/run_config.hpp"
#include "fluid/analytic/analytic_fluid.hpp"
#include "fluid/fluid_solver.hpp"

using namespace coflow;

namespace {

config::Config load(const std::string& dir) { return config::parse_config(dir + "/config.yaml", catalog()); }

fluid::FluidParams fluid_params(const config::Config& cfg) {
  fluid::FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);
  return p;
}

std::string last_snapshot(const std::string& dir) {
  std::ifstream in(dir + "/fluid/index.csv");
  std::string line, last;
  std::getline(in, line);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  if (last.empty()) throw std::runtime_error(dir + ": no fluid snapshot");
  return dir + "/fluid/" + output::snapshot_name(std::stol(last.substr(0, last.find(','))));
}

std::vector<std::vector<double>> read_series(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> r;
    std::stringstream ss(line);
    for (std::string v; std::getline(ss, v, ',');) r.push_back(std::stod(v));
    rows.push_back(r);
  }
  return rows;
}

// Fully developed flow in a rectangular duct, |y| < a, |z| < b, driven by G:
// u = 16 G a^2 / (mu pi^3) sum_{n odd} (-1)^((n-1)/2) / n^3
//       [1 - cosh(n pi z / 2a) / cosh(n pi b / 2a)] cos(n pi y / 2a).
double duct(double y, double z, double a, double b, double G, double mu) {
  double s = 0.0;
  for (int n = 1; n < 200; n += 2) {
    const double k = n * std::numbers::pi / (2 * a);
    const double ratio = std::exp(k * (std::abs(z) - b)) * (1 + std::exp(-2 * k * std::abs(z))) / (1 + std::exp(-2 * k * b));
    s += ((n - 1) / 2 % 2 ? -1.0 : 1.0) / (n * n * n) * (1 - ratio) * std::cos(k * y);
  }
  return 16 * G * a * a / (mu * std::pow(std::numbers::pi, 3)) * s;
}

int profile(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const auto h = d.spacing();
  const double mu = fp.density * fp.viscosity;
  std::vector<std::size_t> dims;
  const auto u = output::read_dataset(last_snapshot(dir), "velocity", &dims);
  const long nz = dims[0], ny = dims[1], nx = dims[2];

  const auto b_xm = fp.boundary(0, cfg), b_xp = fp.boundary(1, cfg), b_yp = fp.boundary(3, cfg);
  // Pressure-driven: Zou-He values act at the centres of the boundary cells.
  double G = fp.body_force[0];
  if (b_xm.type == "pressure" && b_xp.type == "pressure")
    G = (b_xm.value.values[0] - b_xp.value.values[0]) / ((nx - 1) * h[0]);
  const bool couette = b_yp.type == "velocity";
  const bool duct_flow = !d.periodic[2] && nz > 1;
  double err2 = 0.0, ref2 = 0.0;
  for (long k = 0; k < nz; ++k)
    for (long j = 0; j < ny; ++j)
      for (long i = 0; i < nx; ++i) {
        const double y = (j + 0.5) * h[1], z = (k + 0.5) * h[2];
        const double H = ny * h[1], W = nz * h[2];
        double ua;
        if (couette)
          ua = b_yp.value.values[0] * y / ((ny - 0.5) * h[1]);
        else if (duct_flow)
          ua = duct(y - H / 2, z - W / 2, H / 2, W / 2, G, mu);
        else
          ua = G * y * (H - y) / (2 * mu);
        const double un = u[((k * ny + j) * nx + i) * 3];
        err2 += (un - ua) * (un - ua);
        ref2 += ua * ua;
      }
  std::printf("l2_error=%.6e\n", std::sqrt(err2 / ref2));
  return 0;
}

int decay(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const auto rows = read_series(dir + "/series/fluid.csv");
  // Least-squares slope of ln E(t); E ~ exp(-2 nu (kx^2 + ky^2) t) for the 2D vortex.
  double st = 0, se = 0, stt = 0, ste = 0;
  int n = 0;
  for (const auto& r : rows) {
    if (r[0] <= 0) continue;
    const double e = std::log(r[5]);
    st += r[0];
    se += e;
    stt += r[0] * r[0];
    ste += r[0] * e;
    ++n;
  }
  const double slope = (n * ste - st * se) / (n * stt - st * st);
  const double kx = 2 * std::numbers::pi / (d.upper[0] - d.lower[0]), ky = 2 * std::numbers::pi / (d.upper[1] - d.lower[1]);
  const double expected = 2 * fp.viscosity * (kx * kx + ky * ky);
  std::printf("decay_rate=%.9e\nexpected_rate=%.9e\ndecay_rate_error=%.6e\n", -slope, expected,
              std::abs(-slope - expected) / expected);
  return 0;
}

// A ramped pressure face (fluid.boundaries.x-.ramp): the pressure of the x- cells
// in the last snapshot against value x min(1, t / ramp).
int ramp(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto b = fp.boundary(0, cfg);
  if (b.type != "pressure" || b.ramp <= 0.0) throw std::runtime_error("x- is not a ramped pressure face");
  const std::string snap = last_snapshot(dir);
  std::vector<std::size_t> dims;
  const auto p = output::read_dataset(snap, "pressure", &dims);
  double t = 0.0;
  {
    std::ifstream in(dir + "/fluid/index.csv");
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line))
      if (!line.empty()) t = std::stod(line.substr(line.find(',') + 1));
  }
  const long nz = dims[0], ny = dims[1], nx = dims[2];
  const double expected = b.value.values[0] * std::min(1.0, t / b.ramp);
  double worst = 0.0;
  for (long k = 0; k < nz; ++k)
    for (long j = 0; j < ny; ++j) worst = std::max(worst, std::abs(p[(k * ny + j) * nx] - expected));
  std::printf("time=%.6g\ninlet_expected=%.9e\nramp_error=%.6e\n", t, expected, worst / b.value.values[0]);
  return 0;
}

int mass(const std::string& dir) {
  const auto rows = read_series(dir + "/series/fluid.csv");
  double worst = 0.0;
  for (const auto& r : rows) worst = std::max(worst, std::abs(r[1] - rows.front()[1]) / rows.front()[1]);
  std::printf("rows=%zu\nmass_drift=%.6e\n", rows.size(), worst);
  return 0;
}

// Coupled momentum: fluid + particles (series rows at the same times), the
// largest drift of each component relative to the initial total's magnitude, and
// how much momentum moved from the particles to the fluid (so a run in which
// nothing happens cannot pass unnoticed).
int momentum(const std::string& dir) {
  const auto f = read_series(dir + "/series/fluid.csv");
  const auto p = read_series(dir + "/series/particles.csv");
  if (f.size() != p.size() || f.empty()) throw std::runtime_error("fluid and particle series differ in length");
  double p0[3], scale = 0.0;
  for (int d = 0; d < 3; ++d) {
    p0[d] = f[0][2 + d] + p[0][2 + d];
    scale += p0[d] * p0[d];
  }
  scale = std::sqrt(scale);
  // parallel-explicit: the particles take the load of window w in window w + 1,
  // so at the end of window w that load (force x window, from immersed.csv) is
  // still in flight and belongs to the total.
  const auto cfg = load(dir);
  std::vector<std::vector<double>> in_flight;
  double window = 0.0;
  if (cfg.coupling.scheme == "parallel-explicit") {
    in_flight = read_series(dir + "/series/immersed.csv");
    window = cfg.run.end_time / YAML::LoadFile(dir + "/summary.json")["windows"].as<double>();
  }
  double worst = 0.0, moved = 0.0;
  for (std::size_t r = 0; r < f.size(); ++r) {
    if (std::abs(f[r][0] - p[r][0]) > 1e-9 * std::max(1.0, std::abs(f[r][0])))
      throw std::runtime_error("fluid and particle series rows are at different times");
    double pending[3] = {0, 0, 0};
    for (const auto& row : in_flight)
      if (std::abs(row[0] - f[r][0]) <= 1e-9 * std::max(1.0, std::abs(f[r][0])))
        for (int d = 0; d < 3; ++d) pending[d] = row[1 + d] * window;
    double dp = 0.0, fl = 0.0;
    for (int d = 0; d < 3; ++d) {
      const double e = f[r][2 + d] + p[r][2 + d] + pending[d] - p0[d];
      dp += e * e;
      fl += (f[r][2 + d] - f[0][2 + d]) * (f[r][2 + d] - f[0][2 + d]);
    }
    worst = std::max(worst, std::sqrt(dp) / scale);
    moved = std::max(moved, std::sqrt(fl) / scale);
  }
  std::printf("rows=%zu\nmomentum_drift=%.6e\nmomentum_transferred=%.6e\n", f.size(), worst, moved);
  // Resolved particles of one species: the solid volume on the grid against the
  // spheres' volume.
  if (std::ifstream(dir + "/series/immersed.csv") && cfg.resolved["particles"]["species"].size() == 1) {
    const double d = cfg.resolved["particles"]["species"].begin()->second["diameter"].as<double>();
    const auto im = read_series(dir + "/series/immersed.csv");
    double verr = 0.0;
    for (std::size_t r = 0; r < im.size() && r + 1 < p.size(); ++r)  // immersed rows start at window 1
      verr = std::max(verr, std::abs(im[r][7] / (p[r + 1][1] * std::numbers::pi * d * d * d / 6.0) - 1.0));
    std::printf("solid_volume_error=%.6e\n", verr);
  }
  return 0;
}

// Drag on a periodic simple cubic array (one sphere per periodic box, fluid
// driven by a body force): K = f L^3 / (6 pi mu a U) against Zick & Homsy (1982).
int drag(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const double L3 = (d.upper[0] - d.lower[0]) * (d.upper[1] - d.lower[1]) * (d.upper[2] - d.lower[2]);
  double diameter = 0.0;
  for (const auto& sp : cfg.resolved["particles"]["species"]) diameter = sp.second["diameter"].as<double>();
  const double a = 0.5 * diameter, phi = std::numbers::pi * diameter * diameter * diameter / 6.0 / L3;
  const double mu = fp.density * fp.viscosity, f = fp.body_force[0];
  const auto fl = read_series(dir + "/series/fluid.csv");
  const auto im = read_series(dir + "/series/immersed.csv");
  const double U = fl.back()[2] / (fp.density * L3);
  const double F = im.back()[1];
  const double K = f * L3 / (6.0 * std::numbers::pi * mu * a * U);
  // Zick & Homsy (1982), simple cubic arrays.
  const double table[][2] = {{0.027, 2.008}, {0.064, 2.810}, {0.125, 4.292}, {0.216, 7.442}, {0.343, 15.4}};
  double ref = 0.0;
  for (const auto& row : table)
    if (std::abs(phi / row[0] - 1.0) < 0.01) ref = row[1];
  if (ref == 0.0) throw std::runtime_error(fmt::format("solid fraction {:.4f} is not one of Zick & Homsy's", phi));
  // Settled: the force changed by less than 1e-3 over the last fifth of the run.
  const double F_before = im[im.size() * 4 / 5][1];
  std::printf("phi=%.4f\nreynolds=%.3e\nK=%.4f\nK_zick_homsy=%.3f\nK_error=%.4e\nforce_balance=%.4e\nsettling=%.3e\n",
              phi, U * diameter / fp.viscosity, K, ref, std::abs(K / ref - 1.0),
              std::abs(F / (f * (1.0 - phi) * L3) - 1.0), std::abs(F / F_before - 1.0));
  return 0;
}

// Settling sphere of ten Cate et al. (2002): the largest settling speed of the
// (single) particle against the measured terminal velocity of the case, found
// by the fluid's dynamic viscosity (E1-E4).
int settling(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const double mu = fp.density * fp.viscosity;
  const double cases[][3] = {{1, 0.373, 0.0360}, {2, 0.212, 0.0572}, {3, 0.113, 0.0873}, {4, 0.058, 0.1222}};
  int which = 0;
  double ref = 0.0;
  for (const auto& c : cases)
    if (std::abs(mu / c[1] - 1.0) < 0.01) {
      which = static_cast<int>(c[0]);
      ref = c[2];
    }
  if (which == 0) throw std::runtime_error(fmt::format("viscosity {:.4g} Pa s is none of ten Cate's cases", mu));
  double diameter = 0.0, density = 0.0;
  for (const auto& sp : cfg.resolved["particles"]["species"]) {
    diameter = sp.second["diameter"].as<double>();
    density = sp.second["density"].as<double>();
  }
  const double m = density * std::numbers::pi * diameter * diameter * diameter / 6.0;
  const auto rows = read_series(dir + "/series/particles.csv");
  double vmax = 0.0, tmax = 0.0;
  for (const auto& r : rows)
    if (-r[4] / m > vmax) {
      vmax = -r[4] / m;
      tmax = r[0];
    }
  // Still accelerating at the end? The last three rows' increments tell.
  const std::size_t n = rows.size();
  const double late = n > 3 ? (-rows[n - 1][4] + rows[n - 2][4]) / m / std::max(vmax, 1e-300) : 1.0;
  std::printf("case=E%d\nterminal_velocity=%.6f\nten_cate=%.4f\nvelocity_error=%.4e\nat_time=%.3f\nlast_increment=%.3e\n",
              which, vmax, ref, std::abs(vmax / ref - 1.0), tmax, std::abs(late));
  return 0;
}

// A sphere spinning in quiescent fluid: torque against Stokes' 8 pi mu a^3 Omega,
// once the flow has spun up (t > 2 a^2 / nu). Omega from the rotational energy.
int rotation(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const double mu = fp.density * fp.viscosity;
  double diameter = 0.0, density = 0.0;
  for (const auto& sp : cfg.resolved["particles"]["species"]) {
    diameter = sp.second["diameter"].as<double>();
    density = sp.second["density"].as<double>();
  }
  const double a = 0.5 * diameter, m = density * 4.0 / 3.0 * std::numbers::pi * a * a * a, I = 0.4 * m * a * a;
  const auto p = read_series(dir + "/series/particles.csv");
  const auto im = read_series(dir + "/series/immersed.csv");
  const double t0 = 2.0 * a * a / fp.viscosity;
  double worst = 0.0, sum = 0.0, decay = 0.0;
  int n = 0;
  for (const auto& r : im) {
    if (r[0] < t0) continue;
    const auto it = std::find_if(p.begin(), p.end(), [&](const auto& q) { return std::abs(q[0] - r[0]) < 1e-9; });
    if (it == p.end()) continue;
    const double omega = std::sqrt(2.0 * (*it)[9] / I);
    const double ratio = std::abs(r[6]) / (8.0 * std::numbers::pi * mu * a * a * a * omega);
    worst = std::max(worst, std::abs(ratio - 1.0));
    sum += ratio;
    ++n;
    decay = omega;
  }
  if (n == 0) throw std::runtime_error("no rows after the spin-up time");
  const double omega0 = std::sqrt(2.0 * p.front()[9] / I);
  std::printf("rows=%d\ntorque_ratio=%.4f\ntorque_error=%.4e\nspin_left=%.4f\n", n, sum / n, worst,
              decay / omega0);
  return 0;
}

// Kolmogorov-Smirnov distance between the sample x and the distribution cdf.
template <class Cdf>
double ks_distance(std::vector<double> x, Cdf cdf) {
  std::sort(x.begin(), x.end());
  double d = 0.0;
  const double k = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double F = cdf(x[i]);
    d = std::max({d, std::abs(F - i / k), std::abs(F - (i + 1) / k)});
  }
  return d;
}

std::vector<std::pair<long, double>> snapshots(const std::string& dir, const std::string& component) {
  std::ifstream in(dir + "/" + component + "/index.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::pair<long, double>> out;
  while (std::getline(in, line))
    if (!line.empty()) out.emplace_back(std::stol(line.substr(0, line.find(','))), std::stod(line.substr(line.find(',') + 1)));
  return out;
}

// Two-sphere impact: contact duration (from the surface gap, crossings
// interpolated), restitution, energy.
// Point particles settling in a quiescent fluid (dpm): the vertical velocity of
// every particle in the last snapshot against the Schiller-Naumann terminal
// velocity, the root of (rho_p - rho) g pi D^3 / 6 = 3 pi mu D f(Re) v with
// f = 1 + 0.15 Re^0.687, Re = rho D v / mu (seed 003 eqs 2.12, 3.31), by bisection.
int dpm_settling(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const double rho = fp.density, mu = fp.density * fp.viscosity;
  const double g = std::sqrt(cfg.gravity[0] * cfg.gravity[0] + cfg.gravity[1] * cfg.gravity[1] +
                             cfg.gravity[2] * cfg.gravity[2]);
  std::vector<double> densities;
  for (const auto& sp : cfg.resolved["particles"]["species"]) densities.push_back(sp.second["density"].as<double>());
  const auto snaps = snapshots(dir, "particles");
  const std::string last = dir + "/particles/" + output::snapshot_name(snaps.back().first);
  const auto v = output::read_dataset(last, "velocity");
  const auto r = output::read_dataset(last, "radius");
  const auto species = output::read_dataset(last, "species");
  double worst = 0.0, re_max = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double D = 2.0 * r[i], rho_p = densities.at(static_cast<std::size_t>(species[i]));
    const double weight = (rho_p - rho) * g * std::numbers::pi * D * D * D / 6.0;
    auto excess = [&](double u) {
      const double re = rho * D * u / mu;
      return weight - 3.0 * std::numbers::pi * mu * D * (1.0 + 0.15 * std::pow(re, 0.687)) * u;
    };
    double lo = 0.0, hi = weight / (3.0 * std::numbers::pi * mu * D);  // Stokes: an upper bound
    for (int k = 0; k < 200; ++k) (excess(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
    const double vt = 0.5 * (lo + hi);
    const double speed = std::sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
    std::printf("particle %zu: D = %.3g m, terminal %.6f m/s (Schiller-Naumann %.6f, Re %.1f)\n", i, D, speed, vt,
                rho * D * vt / mu);
    worst = std::max(worst, std::abs(speed / vt - 1.0));
    re_max = std::max(re_max, rho * D * vt / mu);
  }
  std::printf("particles=%zu\nreynolds_max=%.2f\nterminal_velocity_error=%.4e\n", r.size(), re_max, worst);
  return 0;
}

// Monodisperse granular gas (seed 003 §5.2): the collision frequency per volume
// against kinetic theory, 2 g0 n^2 D^2 sqrt(pi T) with g0 of Lun & Savage
// (eqs 5.9-5.10, alpha_max 0.64), T the granular temperature from the kinetic
// energy less the mean flow; the Kolmogorov-Smirnov distances of the collision
// angle (pdf sin 2 phi, eq. 5.7 with phi = pi - theta) and of the relative speed
// (eq. 5.8, cdf 1 - (1 + g^2 / 4T) exp(-g^2 / 4T)) from events/collisions.csv,
// each also as a ratio to the 99 % critical value 1.63 / sqrt(count).
int granular_gas_bidisperse(const std::string& dir);

int granular_gas(const std::string& dir) {
  const auto cfg = load(dir);
  if (cfg.resolved["particles"]["species"].size() == 2) return granular_gas_bidisperse(dir);
  const auto& dom = cfg.domain;
  const double V = (dom.upper[0] - dom.lower[0]) * (dom.upper[1] - dom.lower[1]) * (dom.upper[2] - dom.lower[2]);
  const auto sp = cfg.resolved["particles"]["species"].begin()->second;
  const double D = sp["diameter"].as<double>(), rho_p = sp["density"].as<double>();
  const double m = rho_p * std::numbers::pi * D * D * D / 6.0;
  const auto rows = read_series(dir + "/series/particles.csv");
  double collisions = 0.0, T = 0.0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    collisions += rows[r][6];
    const double N = rows[r][1];
    const double p2 = rows[r][2] * rows[r][2] + rows[r][3] * rows[r][3] + rows[r][4] * rows[r][4];
    T += (2.0 * rows[r][5] / (N * m) - p2 / (N * m * N * m)) / 3.0;
  }
  T /= static_cast<double>(rows.size() - 1);
  const double duration = rows.back()[0] - rows.front()[0], N = rows.back()[1];
  const double n = N / V, alpha = N * std::numbers::pi * D * D * D / 6.0 / V;
  const double g0 = std::pow(1.0 - alpha / 0.64, -2.5 * 0.64);
  const double theory = g0 * 2.0 * n * n * D * D * std::sqrt(std::numbers::pi * T);
  const double measured = collisions / duration / V;
  // Event log: angle (degrees), relative speed.
  std::vector<double> angle, speed;
  for (const auto& f : read_series(dir + "/events/collisions.csv")) {  // time,i,j,angle,relative_speed,...
    angle.push_back(f[3] * std::numbers::pi / 180.0);
    speed.push_back(f[4]);
  }
  auto ks = [](std::vector<double> x, auto cdf) { return ks_distance(std::move(x), cdf); };
  const double ks_angle = ks(angle, [](double a) { return std::sin(a) * std::sin(a); });
  const double ks_speed = ks(speed, [&](double g) {
    const double q = g * g / (4.0 * T);
    return 1.0 - (1.0 + q) * std::exp(-q);
  });
  const double critical = 1.63 / std::sqrt(static_cast<double>(angle.size()));
  std::printf("particles=%.0f\nsolid_fraction=%.5f\ngranular_temperature=%.6e\ncollisions=%.0f\n"
              "frequency=%.6e\nfrequency_theory=%.6e\nfrequency_error=%.4e\nevents=%zu\n"
              "angle_ks=%.4e\nangle_ks_ratio=%.3f\nspeed_ks=%.4e\nspeed_ks_ratio=%.3f\n",
              N, alpha, T, collisions, measured, theory, std::abs(measured / theory - 1.0), angle.size(), ks_angle,
              ks_angle / critical, ks_speed, ks_speed / critical);
  return 0;
}

// Bidisperse granular gas (seed 003 §5.2): classes p (small) and q (large).
// Over the second half of the run (equilibrated): collision frequencies per
// volume of p-p, p-q and q-q from events/collisions.csv against kinetic
// theory, f_cc = g0 2 n_c^2 D_c^2 sqrt(pi T_c) (eq. 5.9) and
// f_pq = g0 4 n_p n_q d^2 sqrt(pi (T_p + T_q) / 2), d = (D_p + D_q) / 2, with
// g0 of eqs 5.10 and 5.13-5.15 (eq. 5.12 prints half of that rate: it is
// printed too); the granular temperatures T_c from the snapshots. Energy
// ratios k_p/k_m, k_q/k_m (eq. 5.17) at the start and averaged over the second
// half, against eqs 5.18-5.19.
int granular_gas_bidisperse(const std::string& dir) {
  const auto cfg = load(dir);
  const auto& dom = cfg.domain;
  const double V = (dom.upper[0] - dom.lower[0]) * (dom.upper[1] - dom.lower[1]) * (dom.upper[2] - dom.lower[2]);
  std::vector<double> D, rho;
  for (const auto& sp : cfg.resolved["particles"]["species"]) {
    D.push_back(sp.second["diameter"].as<double>());
    rho.push_back(sp.second["density"].as<double>());
  }
  const int p = D[0] < D[1] ? 0 : 1, q = 1 - p;
  double m[2];
  for (int c = 0; c < 2; ++c) m[c] = rho[c] * std::numbers::pi * D[c] * D[c] * D[c] / 6.0;
  const auto snaps = snapshots(dir, "particles");
  const double t_end = snaps.back().second, t_half = 0.5 * t_end;
  std::vector<int> species_of;
  double n[2] = {0, 0}, T_late[2] = {0, 0}, ratio0[2] = {0, 0}, ratio_late[2] = {0, 0};
  int late = 0;
  for (std::size_t s = 0; s < snaps.size(); ++s) {
    const std::string f = dir + "/particles/" + output::snapshot_name(snaps[s].first);
    const auto id = output::read_dataset(f, "id");
    const auto sp = output::read_dataset(f, "species");
    const auto v = output::read_dataset(f, "velocity");
    if (s == 0) {
      species_of.assign(id.size(), 0);
      for (std::size_t i = 0; i < id.size(); ++i) species_of[static_cast<std::size_t>(id[i])] = static_cast<int>(sp[i]);
    }
    double count[2] = {0, 0}, mean[2][3] = {{0, 0, 0}, {0, 0, 0}}, sq[2] = {0, 0};
    for (std::size_t i = 0; i < id.size(); ++i) {
      const int c = static_cast<int>(sp[i]);
      count[c] += 1;
      for (int d = 0; d < 3; ++d) {
        mean[c][d] += v[3 * i + d];
        sq[c] += v[3 * i + d] * v[3 * i + d];
      }
    }
    double T[2], k[2];
    for (int c = 0; c < 2; ++c) {
      double m2 = 0;
      for (int d = 0; d < 3; ++d) m2 += (mean[c][d] / count[c]) * (mean[c][d] / count[c]);
      T[c] = (sq[c] / count[c] - m2) / 3.0;
      k[c] = 1.5 * T[c];
      n[c] = count[c] / V;
    }
    const double km = (n[0] * m[0] * k[0] + n[1] * m[1] * k[1]) / (n[0] * m[0] + n[1] * m[1]);  // eq. 5.17
    if (s == 0)
      for (int c = 0; c < 2; ++c) ratio0[c] = k[c] / km;
    if (snaps[s].second >= t_half) {
      for (int c = 0; c < 2; ++c) {
        T_late[c] += T[c];
        ratio_late[c] += k[c] / km;
      }
      ++late;
    }
  }
  for (int c = 0; c < 2; ++c) {
    T_late[c] /= late;
    ratio_late[c] /= late;
  }
  double predicted[2];
  for (int c = 0; c < 2; ++c) predicted[c] = (n[0] * m[0] + n[1] * m[1]) / (m[c] * (n[0] + n[1]));  // eqs 5.18-5.19
  // Collisions of the second half, by class pair.
  double counts[3] = {0, 0, 0};  // pp, pq, qq
  for (const auto& f : read_series(dir + "/events/collisions.csv")) {
    if (f[0] < t_half) continue;
    const int a = species_of.at(static_cast<std::size_t>(f[1])), b = species_of.at(static_cast<std::size_t>(f[2]));
    counts[a == b ? (a == p ? 0 : 2) : 1] += 1;
  }
  const double duration = t_end - t_half;
  const double alpha[2] = {n[0] * m[0] / rho[0], n[1] * m[1] / rho[1]}, am = alpha[0] + alpha[1];
  const double g0 = std::pow(1.0 - am / 0.64, -2.5 * 0.64);                            // eq. 5.10
  const double eps = 2.0 * (alpha[p] / D[p] + alpha[q] / D[q]);                        // eq. 5.15
  const double gamma = 1.0 + 1.5 * (D[p] * D[q] / (D[p] + D[q])) * eps / am;           // eq. 5.14
  const double g0pq = std::pow(1.0 - am / 0.64, -gamma * 0.64);                        // eq. 5.13
  const double dpq = 0.5 * (D[p] + D[q]);
  const double theory[3] = {
      g0 * 2.0 * n[p] * n[p] * D[p] * D[p] * std::sqrt(std::numbers::pi * T_late[p]),
      g0pq * 4.0 * n[p] * n[q] * dpq * dpq * std::sqrt(std::numbers::pi * 0.5 * (T_late[p] + T_late[q])),
      g0 * 2.0 * n[q] * n[q] * D[q] * D[q] * std::sqrt(std::numbers::pi * T_late[q])};
  const char* names[3] = {"pp", "pq", "qq"};
  for (int c = 0; c < 3; ++c) {
    const double f = counts[c] / duration / V;
    std::printf("frequency_%s=%.6e\nfrequency_%s_theory=%.6e\nfrequency_%s_error=%.4e\ncollisions_%s=%.0f\n", names[c], f,
                names[c], theory[c], names[c], std::abs(f / theory[c] - 1.0), names[c], counts[c]);
  }
  std::printf("frequency_pq_eq_5_12=%.6e\n", 0.5 * theory[1]);
  std::printf("energy_ratio_p_initial=%.4f\nenergy_ratio_q_initial=%.4f\nenergy_ratio_p=%.4f\nenergy_ratio_q=%.4f\n"
              "energy_ratio_p_theory=%.4f\nenergy_ratio_q_theory=%.4f\nenergy_ratio_error=%.4e\n",
              ratio0[p], ratio0[q], ratio_late[p], ratio_late[q], predicted[p], predicted[q],
              std::max(std::abs(ratio_late[p] / predicted[p] - 1.0), std::abs(ratio_late[q] / predicted[q] - 1.0)));
  return 0;
}

// Two-way momentum exchange (seed 003 §5.1): particles of one species in a
// periodic box of fluid at rest, all starting with the same velocity along x.
// From the series: u_p(t) = P_p / (N m_p), u(t) = P_f / (rho V), against the
// solution of eqs 5.2-5.3 with the Schiller-Naumann drag (integrated with RK4
// at 1/1000 of the response time), and against the closed form 5.4-5.5 with
// the drag factor of the initial slip held constant; errors relative to u_p(0)
// and to the final common velocity u_inf. Momentum (eq. 5.6) relative to P0.
int two_way(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& dom = cfg.domain;
  const double V = (dom.upper[0] - dom.lower[0]) * (dom.upper[1] - dom.lower[1]) * (dom.upper[2] - dom.lower[2]);
  const auto sp = cfg.resolved["particles"]["species"].begin()->second;
  const double D = sp["diameter"].as<double>(), rho_p = sp["density"].as<double>();
  const double rho = fp.density, mu = fp.density * fp.viscosity;
  const double m = rho_p * std::numbers::pi * D * D * D / 6.0, tau = rho_p * D * D / (18.0 * mu);
  const auto f = read_series(dir + "/series/fluid.csv");
  const auto p = read_series(dir + "/series/particles.csv");
  if (f.size() != p.size() || f.size() < 3) throw std::runtime_error("fluid and particle series differ in length");
  const double N = p[0][1], Mp = N * m, Mf = rho * V;
  const double up0 = p[0][2] / Mp, P0 = p[0][2] + f[0][2];
  const double u_inf = P0 / (Mp + Mf);
  auto factor = [&](double slip) { return 1.0 + 0.15 * std::pow(rho * D * std::abs(slip) / mu, 0.687); };
  // Reference: eqs 5.2-5.3.
  double u = f[0][2] / Mf, v = up0, t = 0.0;
  const double h = tau / 1000.0;
  auto rates = [&](double uu, double vv, double& du, double& dv) {
    const double a = factor(uu - vv) / tau * (uu - vv);
    dv = a;
    du = -Mp / Mf * a;
  };
  double worst_p = 0.0, worst_f = 0.0, closed_p = 0.0, closed_f = 0.0, drift = 0.0;
  const double k0 = factor(up0 - u) / tau * (Mp + Mf) / Mf;  // constant-drag rate of eqs 5.4-5.5
  for (std::size_t r = 0; r < f.size(); ++r) {
    while (t < f[r][0] - 0.5 * h) {
      const double step = std::min(h, f[r][0] - t);
      double a1, b1, a2, b2, a3, b3, a4, b4;
      rates(u, v, a1, b1);
      rates(u + 0.5 * step * a1, v + 0.5 * step * b1, a2, b2);
      rates(u + 0.5 * step * a2, v + 0.5 * step * b2, a3, b3);
      rates(u + step * a3, v + step * b3, a4, b4);
      u += step / 6.0 * (a1 + 2 * a2 + 2 * a3 + a4);
      v += step / 6.0 * (b1 + 2 * b2 + 2 * b3 + b4);
      t += step;
    }
    const double up = p[r][2] / Mp, uf = f[r][2] / Mf;
    worst_p = std::max(worst_p, std::abs(up - v) / up0);
    worst_f = std::max(worst_f, std::abs(uf - u) / u_inf);
    const double e = std::exp(-k0 * f[r][0]);
    closed_p = std::max(closed_p, std::abs(up - up0 * (Mp + Mf * e) / (Mp + Mf)) / up0);  // eq. 5.5
    closed_f = std::max(closed_f, std::abs(uf - up0 * Mp / (Mp + Mf) * (1.0 - e)) / u_inf);  // eq. 5.4
    drift = std::max(drift, std::abs(p[r][2] + f[r][2] - P0) / std::abs(P0));
  }
  std::printf("mass_loading=%.4e\nresponse_time=%.6e\nparticle_velocity_error=%.4e\nfluid_velocity_error=%.4e\n"
              "closed_form_particle_error=%.4e\nclosed_form_fluid_error=%.4e\nmomentum_drift=%.4e\n"
              "final_slip=%.4e\n",
              Mp / Mf, tau, worst_p, worst_f, closed_p, closed_f, drift,
              std::abs(p.back()[2] / Mp - f.back()[2] / Mf) / up0);
  return 0;
}

// Particle dispersion in homogeneous turbulence: the mean-square displacement
// along y and z (seed 003 eq. 5.24) from the particle snapshots, against
// Taylor's result for an exponential Lagrangian correlation with the Langevin
// model's T_L = C_T k / epsilon: 2 u'^2 T_L [t - T_L (1 - exp(-t / T_L))],
// u'^2 = 2k/3 (k, epsilon of the analytic fluid's uniform field).
int dispersion(const std::string& dir) {
  const auto cfg = load(dir);
  const auto an = cfg.resolved["fluid"]["analytic"];
  const double k = an["k"].as<double>(), eps = an["epsilon"].as<double>();
  const double CT = cfg.resolved["particles"]["dispersion"]["C_T"].as<double>();
  const double TL = CT * k / eps, u2 = 2.0 * k / 3.0;
  const auto snaps = snapshots(dir, "particles");
  auto positions = [&](long step) {
    const std::string f = dir + "/particles/" + output::snapshot_name(step);
    const auto id = output::read_dataset(f, "id");
    const auto x = output::read_dataset(f, "position");
    std::vector<double> by_id(3 * id.size());
    for (std::size_t i = 0; i < id.size(); ++i)
      for (int d = 0; d < 3; ++d) by_id[3 * static_cast<std::size_t>(id[i]) + d] = x[3 * i + d];
    return by_id;
  };
  const auto x0 = positions(snaps.front().first);
  double worst = 0.0;
  for (std::size_t s = 1; s < snaps.size(); ++s) {
    const double t = snaps[s].second - snaps.front().second;
    const auto x = positions(snaps[s].first);
    if (x.size() != x0.size()) throw std::runtime_error("particles were lost");
    double msd = 0.0;
    const std::size_t n = x.size() / 3;
    for (std::size_t i = 0; i < n; ++i)
      for (int d = 1; d < 3; ++d) msd += (x[3 * i + d] - x0[3 * i + d]) * (x[3 * i + d] - x0[3 * i + d]);
    msd /= 2.0 * static_cast<double>(n);
    const double taylor = 2.0 * u2 * TL * (t - TL * (1.0 - std::exp(-t / TL)));
    std::printf("t = %.3f s: MSD %.5e m^2, Taylor %.5e m^2 (%+.2f %%)\n", t, msd, taylor, 100 * (msd / taylor - 1));
    worst = std::max(worst, std::abs(msd / taylor - 1.0));
  }
  std::printf("lagrangian_time=%.4f\ntrajectories=%zu\nmsd_error=%.4e\n", TL, x0.size() / 3, worst);
  return 0;
}

// Dispersion behind a grid (seed 003 §5.4). For every particle, the crossing of
// x/M = 68.4 (time and lateral position interpolated between snapshots) is the
// reset point; MSD(tau) of eq. 5.24 over y and z, per species, with positions
// interpolated at crossing + tau. Reference: the second moments of the model's
// linear lateral equations along the mean path x(t) = x0 + (U - w) t, w the
// Schiller-Naumann drift (gravity less buoyancy against the flow):
//   u' (fluid velocity seen): Langevin, stationary variance s^2 = 2k/3 (eqs
//      3.35-3.37), decorrelation rate a = 1/T_L + c |slip| / L_E (eqs
//      3.38-3.42: the Eulerian correlation per step of slip r = |slip| dt is
//      1 - c r / L_E), L_E = 3 T_L s;
//   v (particle): dv/dt = (u' - v) / tau_p_eff, tau_p_eff = tau_p / f(Re_w);
//   Y: dY/dt = v.
// d<uu> = 2a(s^2 - <uu>), d<uv> = -a<uv> + (<uu> - <uv>)/tau,
// d<vv> = 2(<uv> - <vv>)/tau, d<uY> = -a<uY> + <uv>,
// d<vY> = (<uY> - <vY>)/tau + <vv>, d<YY> = 2<vY>; <.Y> reset at the crossing.
// The slip's mean length enters a (see s2a); otherwise exact for the model
// with linear drag (the fluctuating slip's effect on f(Re) is neglected).
int grid_turbulence(const std::string& dir) {
  const auto cfg = load(dir);
  const auto an = cfg.resolved["fluid"]["analytic"];
  const int axis = an["flow_axis"].as<int>();
  const double U = an["mean_velocity"].as<double>(), M = an["mesh_size"].as<double>();
  const double x_grid = an["grid_position"].as<double>();
  const double CT = cfg.resolved["particles"]["dispersion"]["C_T"].as<double>();
  const fluid::FluidParams fp = fluid_params(cfg);
  const double rho = fp.density, mu = fp.density * fp.viscosity;
  const double g = std::abs(cfg.resolved["gravity"][axis].as<double>());
  const fluid::GridDecay decay{U, M};
  const double xi_reset = 68.4, x_reset = x_grid + xi_reset * M;
  struct Kind {
    std::string name;
    double D, rho_p;
  };
  std::vector<Kind> kinds;
  for (const auto& sp : cfg.resolved["particles"]["species"])
    kinds.push_back({sp.first.as<std::string>(), sp.second["diameter"].as<double>(), sp.second["density"].as<double>()});
  // Trajectories by id: times and positions of the snapshots holding the particle.
  struct Track {
    int kind = -1;
    std::vector<double> t, x, y, z;
  };
  std::vector<Track> tracks;
  for (const auto& [step, t] : snapshots(dir, "particles")) {
    const std::string f = dir + "/particles/" + output::snapshot_name(step);
    const auto id = output::read_dataset(f, "id");
    const auto sp = output::read_dataset(f, "species");
    const auto x = output::read_dataset(f, "position");
    for (std::size_t i = 0; i < id.size(); ++i) {
      const auto n = static_cast<std::size_t>(id[i]);
      if (n >= tracks.size()) tracks.resize(n + 1);
      Track& tr = tracks[n];
      tr.kind = static_cast<int>(sp[i]);
      tr.t.push_back(t);
      tr.x.push_back(x[3 * i + axis]);
      tr.y.push_back(x[3 * i + (axis + 1) % 3]);
      tr.z.push_back(x[3 * i + (axis + 2) % 3]);
    }
  }
  const double dtau = 0.01;
  const int ntau = 60;
  std::vector<std::vector<double>> sum(kinds.size(), std::vector<double>(ntau + 1, 0.0));
  std::vector<std::vector<long>> count(kinds.size(), std::vector<long>(ntau + 1, 0));
  std::vector<double> t_cross_sum(kinds.size(), 0.0);
  std::vector<long> crossed(kinds.size(), 0), started(kinds.size(), 0);
  for (const Track& tr : tracks) {
    if (tr.kind < 0 || tr.t.size() < 2) continue;
    ++started[tr.kind];
    std::size_t c = 0;
    while (c + 1 < tr.t.size() && !(tr.x[c] < x_reset && tr.x[c + 1] >= x_reset)) ++c;
    if (c + 1 >= tr.t.size()) continue;
    const double s = (x_reset - tr.x[c]) / (tr.x[c + 1] - tr.x[c]);
    const double tc = tr.t[c] + s * (tr.t[c + 1] - tr.t[c]);
    const double y0 = tr.y[c] + s * (tr.y[c + 1] - tr.y[c]), z0 = tr.z[c] + s * (tr.z[c + 1] - tr.z[c]);
    ++crossed[tr.kind];
    t_cross_sum[tr.kind] += tc;
    std::size_t m = c;
    for (int k = 0; k <= ntau; ++k) {
      const double t = tc + k * dtau;
      while (m + 1 < tr.t.size() && tr.t[m + 1] < t) ++m;
      if (m + 1 >= tr.t.size()) break;
      const double r = (t - tr.t[m]) / (tr.t[m + 1] - tr.t[m]);
      const double y = tr.y[m] + r * (tr.y[m + 1] - tr.y[m]) - y0, z = tr.z[m] + r * (tr.z[m + 1] - tr.z[m]) - z0;
      sum[tr.kind][k] += 0.5 * (y * y + z * z);
      ++count[tr.kind][k];
    }
  }
  // The model's moments along the mean path.
  auto model = [&](const Kind& kd, std::vector<double>& msd, double& t_cross) {
    const double tau_p = kd.rho_p * kd.D * kd.D / (18.0 * mu);
    double w = tau_p * g * (1.0 - rho / kd.rho_p), f = 1.0;
    for (int it = 0; it < 100; ++it) {  // drift with the Schiller-Naumann factor
      f = 1.0 + 0.15 * std::pow(rho * kd.D * w / mu, 0.687);
      w = tau_p * g * (1.0 - rho / kd.rho_p) / f;
    }
    const double tau = tau_p / f, speed = U - w;
    double x0 = 0.0;
    long n0 = 0;
    for (const Track& tr : tracks)
      if (tr.kind >= 0 && &kinds[tr.kind] == &kd && !tr.x.empty()) x0 += tr.x.front(), ++n0;
    x0 /= static_cast<double>(std::max(1L, n0));
    t_cross = (x_reset - x0) / speed;
    double uu = 0, uv = 0, vv = 0, uY = 0, vY = 0, YY = 0, t = 0;
    const double h = std::min(tau, 1e-3) / 20.0;
    msd.assign(ntau + 1, 0.0);
    // Variance and decorrelation rate at time tt for the state y: the slip
    // between particle and the fluid it sees has the mean drift w along the
    // flow and lateral fluctuations of variance <(u' - v)^2> per component;
    // its mean length (exact for either part alone) is sqrt(w^2 + 8/pi s_s^2),
    // and R_E of a lateral component averages to 1 - c r / L_E with c = 1.5
    // for a slip across it and 4/3 for an isotropic one (eqs 3.39-3.41).
    auto s2a = [&](double tt, const double* y, double& s2, double& a) {
      const double xi = (x0 + speed * tt - x_grid) / M;
      const double k = decay.k(xi), eps = decay.epsilon(xi), TL = CT * k / eps;
      s2 = 2.0 * k / 3.0;
      const double ss = std::max(0.0, y[0] - 2.0 * y[1] + y[2]);
      const double slip = std::sqrt(w * w + 8.0 / std::numbers::pi * ss);
      const double c = 1.5 - 0.5 * ss / std::max(1e-300, w * w + 3.0 * ss);
      a = 1.0 / TL + c * slip / (3.0 * TL * std::sqrt(s2));
    };
    {
      const double y0[6] = {0, 0, 0, 0, 0, 0};
      double s2, a;
      s2a(0.0, y0, s2, a);
      uu = s2;  // u' starts from the stationary distribution (dispersion.hpp)
    }
    bool reset = false;
    int k = 0;
    while (k <= ntau) {
      if (!reset && t >= t_cross) {
        uY = vY = YY = 0.0;
        reset = true;
      }
      if (reset && t >= t_cross + k * dtau - 0.5 * h) msd[k++] = YY;
      // explicit midpoint on the (nearly linear) system, h << tau, 1/a
      auto rate = [&](double tt, const double* y, double* d) {
        double s2, a;
        s2a(tt, y, s2, a);
        d[0] = 2 * a * (s2 - y[0]);
        d[1] = -a * y[1] + (y[0] - y[1]) / tau;
        d[2] = 2 * (y[1] - y[2]) / tau;
        d[3] = -a * y[3] + y[1];
        d[4] = (y[3] - y[4]) / tau + y[2];
        d[5] = 2 * y[4];
      };
      double y[6] = {uu, uv, vv, uY, vY, YY}, k1[6], ym[6], k2[6];
      rate(t, y, k1);
      for (int i = 0; i < 6; ++i) ym[i] = y[i] + 0.5 * h * k1[i];
      rate(t + 0.5 * h, ym, k2);
      uu += h * k2[0], uv += h * k2[1], vv += h * k2[2], uY += h * k2[3], vY += h * k2[4], YY += h * k2[5];
      t += h;
    }
    return tau;
  };
  std::ofstream csv(dir + "/msd.csv");
  csv << "tau";
  for (const Kind& kd : kinds) csv << ",msd_" << kd.name << ",model_" << kd.name << ",n_" << kd.name;
  csv << "\n";
  std::vector<std::vector<double>> ref(kinds.size());
  std::vector<double> final_msd(kinds.size(), 0.0);
  for (std::size_t q = 0; q < kinds.size(); ++q) {
    double tc_model = 0.0;
    const double tau = model(kinds[q], ref[q], tc_model);
    const double tc = t_cross_sum[q] / static_cast<double>(std::max(1L, crossed[q]));
    std::printf("%s: D %.1f um, rho_p %.0f, tau_p_eff %.4f s, %ld trajectories, %ld reset at x/M = 68.4 (t = %.4f s, "
                "model %.4f s)\n",
                kinds[q].name.c_str(), kinds[q].D * 1e6, kinds[q].rho_p, tau, started[q], crossed[q], tc, tc_model);
  }
  // Compare where every trajectory that was reset is still tracked.
  int kmax = ntau;
  for (std::size_t q = 0; q < kinds.size(); ++q)
    for (int k = 0; k <= ntau; ++k)
      if (count[q][k] < crossed[q]) {
        kmax = std::min(kmax, k - 1);
        break;
      }
  for (int k = 0; k <= kmax; ++k) {
    csv << k * dtau;
    std::printf("tau = %.2f s:", k * dtau);
    for (std::size_t q = 0; q < kinds.size(); ++q) {
      const double msd = sum[q][k] / static_cast<double>(std::max(1L, count[q][k]));
      csv << "," << msd << "," << ref[q][k] << "," << count[q][k];
      std::printf("  %s %.3e (model %.3e)", kinds[q].name.c_str(), msd, ref[q][k]);
      final_msd[q] = msd;
    }
    csv << "\n";
    std::printf("\n");
  }
  // Metrics: model error per kind over tau >= 0.05 s, ordering by Stokes number.
  for (std::size_t q = 0; q < kinds.size(); ++q) {
    double worst = 0.0;
    for (int k = 5; k <= kmax; ++k) {
      const double msd = sum[q][k] / static_cast<double>(count[q][k]);
      worst = std::max(worst, std::abs(msd / ref[q][k] - 1.0));
    }
    std::printf("model_error_%s=%.4e\nreset_fraction_%s=%.4f\n", kinds[q].name.c_str(), worst, kinds[q].name.c_str(),
                static_cast<double>(crossed[q]) / static_cast<double>(std::max(1L, started[q])));
  }
  std::printf("tau_max=%.3f\n", kmax * dtau);
  if (kinds.size() == 4) {
    // Table 5.7: St 0.44, 5.87, 14.69, 14.93; lower Stokes number, larger MSD;
    // particles 3 and 4 alike.
    const bool ordered = final_msd[0] > final_msd[1] && final_msd[1] > final_msd[2] && final_msd[1] > final_msd[3];
    std::printf("stokes_order=%d\nmsd_ratio_p3_p4=%.4f\n", ordered ? 1 : 0, final_msd[2] / final_msd[3]);
  }
  return 0;
}

// A particle inlet (dpm) without forces or collisions: each particle of the
// last snapshot is traced back along its straight path to the inlet plane,
// giving its entry point, time and direction. Injected mass vs mass_flow x
// time (within one largest particle), and Kolmogorov-Smirnov distances, each
// also as a ratio to the 99 % critical value 1.63 / sqrt(n): entry radius
// against r^2/R^2, cos(angle to the jet) against uniform on [cos spread, 1],
// entry time against uniform on [0, t], diameter against the species'
// log-normal (eqs 4.20-4.21, corrected sigma).
int injection(const std::string& dir) {
  const auto cfg = load(dir);
  const auto inj = cfg.resolved["particles"]["injection"][0];
  const auto disk = inj["disk"];
  const std::string species = inj["species"].as<std::string>();
  const auto sp = cfg.resolved["particles"]["species"][species];
  const double rho_p = sp["density"].as<double>();
  const double mean = sp["diameter"]["lognormal"]["mean"].as<double>(), sd = sp["diameter"]["lognormal"]["std"].as<double>();
  const double mdot = inj["mass_flow"].as<double>(), spread = inj["spread_angle"].as<double>() * std::numbers::pi / 180.0;
  const auto c3 = disk["center"].as<std::vector<double>>(), n3 = disk["normal"].as<std::vector<double>>();
  const double R = 0.5 * disk["diameter"].as<double>();
  const auto last = snapshots(dir, "particles").back();
  const std::string f = dir + "/particles/" + output::snapshot_name(last.first);
  const double t_end = last.second;
  const auto x = output::read_dataset(f, "position"), v = output::read_dataset(f, "velocity");
  const auto rad = output::read_dataset(f, "radius");
  const std::size_t n = rad.size();
  double nn = std::sqrt(n3[0] * n3[0] + n3[1] * n3[1] + n3[2] * n3[2]);
  const double nrm[3] = {n3[0] / nn, n3[1] / nn, n3[2] / nn};
  std::vector<double> r2, cosang, tin, diam;
  double mass = 0.0, dmax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double D = 2.0 * rad[i];
    mass += rho_p * std::numbers::pi * D * D * D / 6.0;
    dmax = std::max(dmax, D);
    diam.push_back(D);
    double h = 0.0, vn = 0.0, speed = 0.0;
    for (int k = 0; k < 3; ++k) {
      h += (x[3 * i + k] - c3[k]) * nrm[k];
      vn += v[3 * i + k] * nrm[k];
      speed += v[3 * i + k] * v[3 * i + k];
    }
    speed = std::sqrt(speed);
    const double back = h / vn;  // time since entry
    double rr = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double p = x[3 * i + k] - v[3 * i + k] * back - c3[k];
      rr += p * p;
    }
    r2.push_back(std::sqrt(rr));
    cosang.push_back(vn / speed);
    tin.push_back(t_end - back);
  }
  const double cap = mean + 6.0 * sd;  // the largest diameter an inlet draws
  const double expected = mdot * t_end, m_big = rho_p * std::numbers::pi * cap * cap * cap / 6.0;
  const double crit = 1.63 / std::sqrt(static_cast<double>(n));
  const double ks_r = ks_distance(r2, [&](double r) { return std::min(1.0, r * r / (R * R)); });
  const double cs = std::cos(spread);
  const double ks_c = ks_distance(cosang, [&](double c) { return std::clamp((c - cs) / (1.0 - cs), 0.0, 1.0); });
  const double ks_t = ks_distance(tin, [&](double t) { return std::clamp(t / t_end, 0.0, 1.0); });
  const double s2 = std::log(1.0 + sd * sd / (mean * mean)), mu = std::log(mean) - 0.5 * s2;
  const double ks_d = ks_distance(diam, [&](double D) { return 0.5 * std::erfc(-(std::log(D) - mu) / std::sqrt(2.0 * s2)); });
  double sum = 0.0, sum2 = 0.0;
  for (double D : diam) sum += D, sum2 += D * D;
  const double dm = sum / n, ds = std::sqrt(sum2 / n - dm * dm);
  std::printf("particles=%zu\ninjected_mass=%.6e\nexpected_mass=%.6e\nmass_deficit_in_particles=%.4f\n"
              "mean_diameter=%.5e\nstd_diameter=%.5e\nradius_ks_ratio=%.3f\ndirection_ks_ratio=%.3f\n"
              "time_ks_ratio=%.3f\ndiameter_ks_ratio=%.3f\nmax_entry_radius_over_R=%.6f\nmin_cos_over_cos_spread=%.6f\n",
              n, mass, expected, (expected - mass) / m_big, dm, ds, ks_r / crit, ks_c / crit, ks_t / crit, ks_d / crit,
              *std::max_element(r2.begin(), r2.end()) / R, *std::min_element(cosang.begin(), cosang.end()) / cs);
  return 0;
}

// Granular jet on a plate (seed 003 §5.3): the impacts on the mesh walls
// (events/impacts.csv, wall >= 6): count, mean, min and max impact angle
// (between the velocity and the plate's plane, 90 = head-on) and the largest
// deviation from 90 degrees.
int jet(const std::string& dir) {
  const auto rows = read_series(dir + "/events/impacts.csv");  // time,id,wall,x,y,z,angle,speed
  long n = 0;
  double sum = 0.0, lo = 1e300, hi = -1e300, dev = 0.0, speed = 0.0;
  for (const auto& r : rows) {
    if (r[2] < 6) continue;
    ++n;
    sum += r[6];
    lo = std::min(lo, r[6]);
    hi = std::max(hi, r[6]);
    dev = std::max(dev, std::abs(r[6] - 90.0));
    speed += r[7];
  }
  if (n == 0) throw std::runtime_error("no impact on a mesh wall in " + dir + "/events/impacts.csv");
  std::printf("plate_impacts=%ld\nmean_angle=%.12f\nmin_angle=%.6f\nmax_angle=%.6f\nangle_deviation=%.4e\n"
              "mean_impact_speed=%.6f\n",
              n, sum / n, lo, hi, dev, speed / n);
  return 0;
}

int impact(const std::string& dir) {
  const auto cfg = load(dir);
  double t_in = -1, t_out = -1, prev_gap = 0, prev_t = 0, v0 = 0, v1 = 0, r = 0, rho = 0;
  bool first = true;
  for (const auto& [step, t] : snapshots(dir, "particles")) {
    const std::string f = dir + "/particles/" + output::snapshot_name(step);
    const auto x = output::read_dataset(f, "position");
    const auto v = output::read_dataset(f, "velocity");
    const auto rad = output::read_dataset(f, "radius");
    const double dx = x[3] - x[0], dy = x[4] - x[1], dz = x[5] - x[2];
    const double gap = std::sqrt(dx * dx + dy * dy + dz * dz) - rad[0] - rad[1];
    const double vrel = v[3] - v[0];
    if (first) {
      v0 = vrel;
      r = rad[0];
    }
    if (!first && prev_gap > 0 && gap <= 0) t_in = prev_t + (t - prev_t) * prev_gap / (prev_gap - gap);
    if (!first && prev_gap <= 0 && gap > 0) t_out = prev_t + (t - prev_t) * (-prev_gap) / (gap - prev_gap);
    v1 = vrel;
    prev_gap = gap;
    prev_t = t;
    first = false;
  }
  YAML::Node sp = cfg.resolved["particles"]["species"].begin()->second;
  rho = std::stod(sp["density"].Scalar());
  const double kn = std::stod(cfg.resolved["particles"]["contact"]["normal_stiffness"].Scalar());
  const double m = rho * std::numbers::pi * 8 * r * r * r / 6.0;
  const double expected = std::numbers::pi * std::sqrt(0.5 * m / kn);
  const auto rows = read_series(dir + "/series/particles.csv");
  const double e0 = rows.front()[5], e1 = rows.back()[5];
  std::printf("contact_duration=%.9e\nexpected_duration=%.9e\nduration_error=%.6e\nrestitution=%.9f\n"
              "energy_error=%.6e\n",
              t_out - t_in, expected, std::abs(t_out - t_in - expected) / expected, std::abs(v1 / v0),
              std::abs(e1 - e0) / e0);
  return 0;
}

// Gravity pour: translational kinetic energy at the end relative to its peak,
// and the packing fraction of the bulk (2 diameters from the walls and the
// bottom, 4 below the free surface), by point sampling.
int pour(const std::string& dir) {
  const auto rows = read_series(dir + "/series/particles.csv");
  double peak = 0;
  for (const auto& r : rows) peak = std::max(peak, r[5]);
  const auto snaps = snapshots(dir, "particles");
  const std::string f = dir + "/particles/" + output::snapshot_name(snaps.back().first);
  const auto x = output::read_dataset(f, "position");
  const auto rad = output::read_dataset(f, "radius");
  const std::size_t n = rad.size();
  const auto cfg = load(dir);
  double rmax = 0;
  std::vector<double> zs;
  for (std::size_t i = 0; i < n; ++i) {
    rmax = std::max(rmax, rad[i]);
    zs.push_back(x[3 * i + 2]);
  }
  std::sort(zs.begin(), zs.end());
  double top = 0;
  const std::size_t k = std::min<std::size_t>(50, n);
  for (std::size_t i = n - k; i < n; ++i) top += zs[i] / k;
  const double d = 2 * rmax;
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = cfg.domain.lower[a] + 2 * d;
    hi[a] = a == 2 ? top - 4 * d : cfg.domain.upper[a] - 2 * d;
  }
  // Spheres bucketed on a grid of cell size d.
  int nc[3];
  for (int a = 0; a < 3; ++a) nc[a] = std::max(1, static_cast<int>((cfg.domain.upper[a] - cfg.domain.lower[a]) / d));
  std::vector<std::vector<std::size_t>> grid(static_cast<std::size_t>(nc[0]) * nc[1] * nc[2]);
  auto cell = [&](double v, int a) {
    return std::clamp(static_cast<int>((v - cfg.domain.lower[a]) / (cfg.domain.upper[a] - cfg.domain.lower[a]) * nc[a]), 0, nc[a] - 1);
  };
  for (std::size_t i = 0; i < n; ++i)
    grid[(cell(x[3 * i + 2], 2) * nc[1] + cell(x[3 * i + 1], 1)) * nc[0] + cell(x[3 * i], 0)].push_back(i);
  const int m = 60;
  long in = 0, total = 0;
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b)
      for (int c = 0; c < m; ++c) {
        const double p[3] = {lo[0] + (a + 0.5) * (hi[0] - lo[0]) / m, lo[1] + (b + 0.5) * (hi[1] - lo[1]) / m,
                             lo[2] + (c + 0.5) * (hi[2] - lo[2]) / m};
        const int ci[3] = {cell(p[0], 0), cell(p[1], 1), cell(p[2], 2)};
        bool solid = false;
        for (int dz = -1; dz <= 1 && !solid; ++dz)
          for (int dy = -1; dy <= 1 && !solid; ++dy)
            for (int dx = -1; dx <= 1 && !solid; ++dx) {
              const int q[3] = {ci[0] + dx, ci[1] + dy, ci[2] + dz};
              if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= nc[0] || q[1] >= nc[1] || q[2] >= nc[2]) continue;
              for (std::size_t i : grid[(q[2] * nc[1] + q[1]) * nc[0] + q[0]]) {
                const double ddx = p[0] - x[3 * i], ddy = p[1] - x[3 * i + 1], ddz = p[2] - x[3 * i + 2];
                if (ddx * ddx + ddy * ddy + ddz * ddz < rad[i] * rad[i]) {
                  solid = true;
                  break;
                }
              }
            }
        in += solid;
        ++total;
      }
  std::printf("particles=%zu\nbed_top=%.6f\nkinetic_energy_ratio=%.6e\nrotational_energy=%.6e\npacking_fraction=%.4f\n",
              n, top, rows.back()[5] / peak, rows.back().size() > 9 ? rows.back()[9] : 0.0,
              static_cast<double>(in) / total);
  return 0;
}

// Particle snapshots of two runs: largest position difference over the diameter.
int compare_particles(const std::string& a, const std::string& b) {
  const auto sa = snapshots(a, "particles"), sb = snapshots(b, "particles");
  const std::string fa = a + "/particles/" + output::snapshot_name(sa.back().first);
  const std::string fb = b + "/particles/" + output::snapshot_name(sb.back().first);
  // Snapshots of different rank counts hold the particles in different orders:
  // compare by id.
  auto by_id = [](const std::string& f, const std::string& name, int nc) {
    const auto id = output::read_dataset(f, "id");
    const auto v = output::read_dataset(f, name);
    std::vector<std::size_t> order(id.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) { return id[p] < id[q]; });
    std::vector<double> out;
    for (std::size_t i : order)
      for (int c = 0; c < nc; ++c) out.push_back(v[nc * i + c]);
    return out;
  };
  const auto xa = by_id(fa, "position", 3), xb = by_id(fb, "position", 3);
  const auto va = by_id(fa, "velocity", 3), vb = by_id(fb, "velocity", 3);
  const auto ra = by_id(fa, "radius", 1);
  if (xa.size() != xb.size()) throw std::runtime_error("particle counts differ");
  double dx = 0, dv = 0, vmax = 0, dmin = 1e300;
  for (std::size_t i = 0; i < xa.size(); ++i) {
    dx = std::max(dx, std::abs(xa[i] - xb[i]));
    dv = std::max(dv, std::abs(va[i] - vb[i]));
    vmax = std::max(vmax, std::abs(va[i]));
  }
  for (double r : ra) dmin = std::min(dmin, 2 * r);
  std::printf("particles=%zu\nposition_difference=%.6e\nvelocity_difference=%.6e\n", ra.size(), dx / dmin,
              vmax > 0 ? dv / vmax : dv);
  return 0;
}

int compare(const std::string& a, const std::string& b) {
  if (!std::ifstream(a + "/fluid/index.csv")) return compare_particles(a, b);
  const auto ua = output::read_dataset(last_snapshot(a), "velocity");
  const auto ub = output::read_dataset(last_snapshot(b), "velocity");
  if (ua.size() != ub.size()) throw std::runtime_error("snapshots differ in size");
  double diff = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < ua.size(); ++i) {
    diff = std::max(diff, std::abs(ua[i] - ub[i]));
    scale = std::max(scale, std::abs(ua[i]));
  }
  const auto pa = output::read_dataset(last_snapshot(a), "pressure");
  const auto pb = output::read_dataset(last_snapshot(b), "pressure");
  double pdiff = 0.0, pscale = 0.0;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    pdiff = std::max(pdiff, std::abs(pa[i] - pb[i]));
    pscale = std::max(pscale, std::abs(pa[i]));
  }
  std::printf("max_velocity=%.6e\nmax_difference=%.6e\npressure_difference=%.6e\n", scale, diff / scale,
              pscale > 0 ? pdiff / pscale : pdiff);
  // Coupled runs: the particles too.
  if (std::ifstream(a + "/particles/index.csv")) return compare_particles(a, b);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string what = argc > 1 ? argv[1] : "";
    if (what == "profile" && argc == 3) return profile(argv[2]);
    if (what == "decay" && argc == 3) return decay(argv[2]);
    if (what == "mass" && argc == 3) return mass(argv[2]);
    if (what == "ramp" && argc == 3) return ramp(argv[2]);
    if (what == "compare" && argc == 4) return compare(argv[2], argv[3]);
    if (what == "impact" && argc == 3) return impact(argv[2]);
    if (what == "pour" && argc == 3) return pour(argv[2]);
    if (what == "momentum" && argc == 3) return momentum(argv[2]);
    if (what == "drag" && argc == 3) return drag(argv[2]);
    if (what == "settling" && argc == 3) return settling(argv[2]);
    if (what == "dpm_settling" && argc == 3) return dpm_settling(argv[2]);
    if (what == "granular_gas" && argc == 3) return granular_gas(argv[2]);
    if (what == "two_way" && argc == 3) return two_way(argv[2]);
    if (what == "dispersion" && argc == 3) return dispersion(argv[2]);
    if (what == "grid_turbulence" && argc == 3) return grid_turbulence(argv[2]);
    if (what == "injection" && argc == 3) return injection(argv[2]);
    if (what == "jet" && argc == 3) return jet(argv[2]);
    if (what == "rotation" && argc == 3) return rotation(argv[2]);
    std::fprintf(stderr, "usage: coflow-check profile|decay|mass RUN_DIR | compare RUN_A RUN_B\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "coflow-check: %s\n", e.what());
    return 1;
  }
}
