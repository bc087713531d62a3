// coflow-check: resolved particles (psm): momentum, drag array, settling sphere, rotating sphere.
#include "../check/check.hpp"

namespace coflow::check {

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
  if (cfg.coupling.scheme == coflow::config::Scheme::parallel_explicit) {
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
    worst = nan_max(worst, std::sqrt(dp) / scale);
    moved = nan_max(moved, std::sqrt(fl) / scale);
  }
  std::printf("rows=%zu\nmomentum_drift=%.6e\nmomentum_transferred=%.6e\n", f.size(), worst, moved);
  // Resolved particles of one species: the solid volume on the grid against the
  // spheres' volume.
  if (std::ifstream(dir + "/series/immersed.csv") && cfg.resolved["particles"]["species"].size() == 1) {
    const double d = cfg.resolved["particles"]["species"].begin()->second["diameter"].as<double>();
    const auto im = read_series(dir + "/series/immersed.csv");
    double verr = 0.0;
    for (std::size_t r = 0; r < im.size() && r + 1 < p.size(); ++r)  // immersed rows start at window 1
      verr = nan_max(verr, std::abs(im[r][7] / (p[r + 1][1] * std::numbers::pi * d * d * d / 6.0) - 1.0));
    std::printf("solid_volume_error=%.6e\n", verr);
  }
  return 0;
}

// Drag on a periodic simple cubic array (one sphere per periodic box, fluid
// driven by a body force): K = f L^3 / (6 pi mu a U) against Zick & Homsy (1982).
// At steady state the sphere holds the whole box against the driving gradient
// f: the fluid takes 1 - B of the body force in each cell and passes it on to
// the sphere as drag, the sphere takes B (fluid/lbm/psm_kernel.hpp).
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
  std::printf(
      "phi=%.4f\nreynolds=%.3e\nK=%.4f\nK_zick_homsy=%.3f\nK_error=%.4e\nforce_balance=%.4e\nsettling=%.3e\n",
      phi, U * diameter / fp.viscosity, K, ref, std::abs(K / ref - 1.0), std::abs(F / (f * L3) - 1.0),
      std::abs(F / F_before - 1.0));
  return 0;
}

// A fixed sphere in a closed box of fluid at rest whose body force is its own
// weight, f = rho_f g: the fluid's pressure carries the weight, and the load
// on the sphere is Archimedes' buoyancy -rho_f V g, whatever the sphere weighs.
// The load's change over the last fifth of the run says whether the start's
// sound waves have died down.
int buoyancy(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  double diameter = 0.0;
  for (const auto& sp : cfg.resolved["particles"]["species"]) diameter = sp.second["diameter"].as<double>();
  const double volume = std::numbers::pi * diameter * diameter * diameter / 6.0;
  const auto& g = cfg.gravity;
  for (int d = 0; d < 3; ++d)
    if (std::abs(fp.body_force[d] - fp.density * g[d]) > 1e-12 * std::abs(fp.density * g[d]))
      throw std::runtime_error("buoyancy: fluid.body_force must be the fluid's weight, density x gravity");
  const auto im = read_series(dir + "/series/immersed.csv");
  if (im.size() < 5) throw std::runtime_error("buoyancy: fewer than 5 rows in immersed.csv");
  const auto& last = im.back();
  const auto& before = im[im.size() * 4 / 5];
  const double gg = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]), archimedes = fp.density * volume * gg;
  if (!(archimedes > 0.0)) throw std::runtime_error("buoyancy: no gravity, no buoyancy to compare with");
  double err = 0.0, change = 0.0;
  for (int d = 0; d < 3; ++d) {
    err += std::pow(last[1 + d] + fp.density * volume * g[d], 2);
    change += std::pow(last[1 + d] - before[1 + d], 2);
  }
  std::printf("archimedes=%.6e\nload_along_g=%.6e\nbuoyancy_error=%.4e\nsettling=%.3e\n", archimedes,
              (last[1] * g[0] + last[2] * g[1] + last[3] * g[2]) / gg, std::sqrt(err) / archimedes,
              std::sqrt(change) / archimedes);
  return 0;
}

// Settling sphere of ten Cate et al. (2002): the largest settling speed of the
// (single) particle against the measured terminal velocity of the case, found
// by the fluid's dynamic viscosity (E1-E4).
int settling(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const double mu = fp.density * fp.viscosity;
  const double cases[][3] = {{1, 0.373, 0.038}, {2, 0.212, 0.060}, {3, 0.113, 0.091}, {4, 0.058, 0.128}};
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
    require_finite({r.at(4)}, "series/particles.csv: the sphere's momentum at t = " + std::to_string(r[0]));
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

// A sphere spinning steadily in quiescent fluid: torque against Stokes'
// 8 pi mu a^3 Omega, averaged over the last 0.5 s (the flow has spun up), and
// how much that ratio still changed between the two halves of that time.
// Omega from the rotational energy.
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
  const double t_end = im.back()[0];
  double sum[2] = {0.0, 0.0};
  int n[2] = {0, 0};
  for (const auto& r : im) {
    if (r[0] < t_end - 0.5) continue;
    const auto it = std::find_if(p.begin(), p.end(), [&](const auto& q) { return std::abs(q[0] - r[0]) < 1e-9; });
    if (it == p.end()) continue;
    const double omega = std::sqrt(2.0 * (*it)[9] / I);
    const int half = r[0] < t_end - 0.25 ? 0 : 1;
    sum[half] += std::abs(r[6]) / (8.0 * std::numbers::pi * mu * a * a * a * omega);
    ++n[half];
  }
  if (n[0] == 0 || n[1] == 0) throw std::runtime_error("too few rows in the last 0.5 s");
  const double early = sum[0] / n[0], late = sum[1] / n[1], ratio = (sum[0] + sum[1]) / (n[0] + n[1]);
  std::printf("rows=%d\ntorque_ratio=%.4f\ntorque_error=%.4e\ntorque_drift=%.4e\n", n[0] + n[1], ratio,
              std::abs(ratio - 1.0), std::abs(late / early - 1.0));
  // The torque's direction: against the spin (T . Omega < 0) and along its
  // axis; the net force on the spinning sphere vanishes, so a lever taken from
  // the wrong point would show as torque off the axis. Over the last 0.5 s.
  const auto w = output::read_dataset(last_snapshot(dir, "particles"), "angular_velocity");
  const double wn = std::hypot(w[0], w[1], w[2]);
  double worst_along = -1e300, worst_off = 0.0;
  int used = 0;
  for (const auto& r : im) {
    if (r[0] < t_end - 0.5) continue;
    const double t[3] = {r[4], r[5], r[6]}, tn = std::hypot(t[0], t[1], t[2]);
    const double along = (t[0] * w[0] + t[1] * w[1] + t[2] * w[2]) / (tn * wn);  // -1: against the spin
    worst_along = std::isnan(along) ? along : std::max(worst_along, along);
    // sin of the angle from |T x Omega| (1 - cos^2 loses its digits near 0).
    const double off =
        std::hypot(t[1] * w[2] - t[2] * w[1], t[2] * w[0] - t[0] * w[2], t[0] * w[1] - t[1] * w[0]) /
        (tn * wn);
    worst_off = std::isnan(off) ? off : std::max(worst_off, off);
    ++used;
  }
  if (used == 0) throw std::runtime_error("no immersed.csv row in the last 0.5 s");
  std::printf("torque_against_spin=%.6e\ntorque_off_axis=%.6e\n", 1.0 + worst_along, worst_off);
  return 0;
}

}  // namespace coflow::check
