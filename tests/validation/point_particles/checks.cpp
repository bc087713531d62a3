// coflow-check: point particles (dpm): settling, granular gases, two-way coupling, dispersion, grid turbulence, injection, jet on a plate.
#include <functional>
#include "../check/check.hpp"

namespace coflow::check {

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
    worst = nan_max(worst, std::abs(speed / vt - 1.0));
    re_max = nan_max(re_max, rho * D * vt / mu);
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
  if (angle.empty())  // the KS statistics of no events would print 0 and pass
    throw std::runtime_error(dir +
                             "/events/collisions.csv: no collision events (run.output.events: [collisions])");
  auto ks = [](std::vector<double> x, auto cdf) { return ks_distance(std::move(x), cdf); };
  const double ks_angle = ks(angle, [](double a) { return std::sin(a) * std::sin(a); });
  const double ks_speed = ks(speed, [&](double g) {
    const double q = g * g / (4.0 * T);
    return 1.0 - (1.0 + q) * std::exp(-q);
  });
  const double critical = 1.63 / std::sqrt(static_cast<double>(angle.size()));
  std::printf(
      "particles=%.0f\nsolid_fraction=%.6e\ngranular_temperature=%.6e\ncollisions=%.0f\n"
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
  std::printf(
      "energy_ratio_p_initial=%.4f\nenergy_ratio_q_initial=%.4f\nenergy_ratio_p=%.4f\nenergy_ratio_q=%.4f\n"
      "energy_ratio_p_theory=%.4f\nenergy_ratio_q_theory=%.4f\nenergy_ratio_error=%.4e\n",
      ratio0[p], ratio0[q], ratio_late[p], ratio_late[q], predicted[p], predicted[q],
      nan_max(std::abs(ratio_late[p] / predicted[p] - 1.0), std::abs(ratio_late[q] / predicted[q] - 1.0)));
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
    worst_p = nan_max(worst_p, std::abs(up - v) / up0);
    worst_f = nan_max(worst_f, std::abs(uf - u) / u_inf);
    const double e = std::exp(-k0 * f[r][0]);
    closed_p = nan_max(closed_p, std::abs(up - up0 * (Mp + Mf * e) / (Mp + Mf)) / up0);     // eq. 5.5
    closed_f = nan_max(closed_f, std::abs(uf - up0 * Mp / (Mp + Mf) * (1.0 - e)) / u_inf);  // eq. 5.4
    drift = nan_max(drift, std::abs(p[r][2] + f[r][2] - P0) / std::abs(P0));
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
    worst = nan_max(worst, std::abs(msd / taylor - 1.0));
  }
  std::printf("lagrangian_time=%.4f\ntrajectories=%zu\nmsd_error=%.4e\n", TL, x0.size() / 3, worst);
  return 0;
}

// A particle kind for the dispersion models: name, diameter, density.
struct MsdKind {
  std::string name;
  double D, rho_p;
};
// The fluid and the path for model_msd: mean velocity, gravity against the
// flow, density and dynamic viscosity, C_T, the start and reset positions
// along the flow, and k and epsilon at a position along it.
struct MsdModel {
  double U, g, rho, mu, CT, x0, x_reset;
  std::function<void(double x, double& k, double& eps)> turbulence;
};

// The model's lateral moments along the mean path (see grid_turbulence) for
// particles of kind kd entering at m.x0; MSD after the reset at m.x_reset
// every dtau (ntau + 1 values) and the model's crossing time. Returns the
// particle's effective relaxation time.
double model_msd(const MsdModel& m, const MsdKind& kd, double dtau, int ntau, std::vector<double>& msd,
                 double& t_cross) {
  const double U = m.U, g = m.g, rho = m.rho, mu = m.mu, CT = m.CT, x_reset = m.x_reset;
  const double tau_p = kd.rho_p * kd.D * kd.D / (18.0 * mu);
  double w = tau_p * g * (1.0 - rho / kd.rho_p), f = 1.0;
  for (int it = 0; it < 100; ++it) {  // drift with the Schiller-Naumann factor
    f = 1.0 + 0.15 * std::pow(rho * kd.D * w / mu, 0.687);
    w = tau_p * g * (1.0 - rho / kd.rho_p) / f;
  }
  const double tau = tau_p / f, speed = U - w;
  const double x0 = m.x0;
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
    double k, eps;
    m.turbulence(x0 + speed * tt, k, eps);
    const double TL = CT * k / eps;
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
  std::vector<MsdKind> kinds;
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
  std::vector<double> x0_sum(kinds.size(), 0.0);
  std::vector<long> n0(kinds.size(), 0);
  for (const Track& tr : tracks)
    if (tr.kind >= 0 && static_cast<std::size_t>(tr.kind) < kinds.size() && !tr.x.empty())
      x0_sum[static_cast<std::size_t>(tr.kind)] += tr.x.front(), ++n0[static_cast<std::size_t>(tr.kind)];
  auto model = [&](const MsdKind& kd, std::vector<double>& msd, double& t_cross) {
    const auto q = static_cast<std::size_t>(&kd - kinds.data());
    const MsdModel m{U, g, rho, mu, CT, x0_sum[q] / static_cast<double>(std::max(1L, n0[q])), x_reset,
                     [&](double x, double& k, double& e) {
                       const double xi = (x - x_grid) / M;
                       k = decay.k(xi), e = decay.epsilon(xi);
                     }};
    return model_msd(m, kd, dtau, ntau, msd, t_cross);
  };
  std::ofstream csv(dir + "/msd.csv");
  csv << "tau";
  for (const MsdKind& kd : kinds) csv << ",msd_" << kd.name << ",model_" << kd.name << ",n_" << kd.name;
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
      worst = nan_max(worst, std::abs(msd / ref[q][k] - 1.0));
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

// Dispersion on a computed carrier flow (fv with k-epsilon): the run's own
// series/dispersion.csv (particles.dispersion.msd, eq. 5.24) against the
// model's moments along the mean path (model_msd) in the k and epsilon the
// fluid carries: k-epsilon's exact decay from its inlet (U dk/dx = -epsilon, U
// depsilon/dx = -C_e2 epsilon^2/k; coflow-check ke_grid holds the fluid to it
// within 1.6 %). The particles enter at the first injection's centre.
int grid_turbulence_fv(const std::string& dir) {
  const auto cfg = load(dir);
  const fluid::FluidParams fp = fluid_params(cfg);
  fluid::TurbulenceParams t = fp.turbulence;  // with the k and epsilon entering through the inlet (below)
  const auto disp = cfg.resolved["particles"]["dispersion"];
  const auto msd_cfg = disp["msd"];
  const int axis = msd_cfg["axis"].as<int>();
  const double U = fp.boundary(2 * axis, cfg).value.values.at(static_cast<std::size_t>(axis));
  const double x_in = cfg.domain.lower[axis], n = 1.0 / (t.constants.C_epsilon2 - 1.0);
  const auto inlets = fp.inlet_turbulence(cfg);
  if (inlets.varies(2 * axis))
    throw std::runtime_error("this check needs uniform k and epsilon at the inlet");
  t.inlet_k = inlets.k[static_cast<std::size_t>(2 * axis)];
  t.inlet_epsilon = inlets.epsilon[static_cast<std::size_t>(2 * axis)];
  const double x0 = cfg.resolved["particles"]["injection"][0]["disk"]["center"][axis].as<double>();
  const double dtau = msd_cfg["interval"].as<double>();
  const int ntau = msd_cfg["samples"].as<int>();
  MsdModel m{U,
             std::abs(cfg.resolved["gravity"][axis].as<double>()),
             fp.density,
             fp.density * fp.viscosity,
             disp["C_T"].as<double>(),
             x0,
             msd_cfg["plane"].as<double>(),
             [&](double x, double& k, double& e) {
               const double base = 1.0 + (t.constants.C_epsilon2 - 1.0) * t.inlet_epsilon * (x - x_in) / (U * t.inlet_k);
               k = t.inlet_k * std::pow(base, -n), e = t.inlet_epsilon * std::pow(base, -n - 1.0);
             }};
  const auto rows = read_series(dir + "/series/dispersion.csv");
  std::vector<MsdKind> kinds;
  for (const auto& sp : cfg.resolved["particles"]["species"])
    kinds.push_back({sp.first.as<std::string>(), sp.second["diameter"].as<double>(), sp.second["density"].as<double>()});
  const std::size_t K = kinds.size();
  std::vector<double> final_msd(K, 0.0);
  std::vector<std::vector<double>> refs(K);
  for (std::size_t q = 0; q < K; ++q) {
    std::vector<double>& ref = refs[q];
    double tc = 0.0;
    model_msd(m, kinds[q], dtau, ntau, ref, tc);
    const double started = rows.at(0).at(1 + K + q);
    double worst = 0.0;
    int used = 0;
    for (std::size_t k = 5; k < rows.size() && k < ref.size(); ++k) {
      if (rows[k][1 + K + q] < started) break;  // compare while every crossed particle is tracked
      const double e = std::abs(rows[k][1 + q] / ref[k] - 1.0);
      worst = nan_max(worst, e);  // NaN sticks
      final_msd[q] = rows[k][1 + q];
      ++used;
    }
    std::printf("%s: %.0f particles crossed; model crossing at t = %.4f s; %d rows compared\n", kinds[q].name.c_str(),
                started, tc, used);
    std::printf("model_error_%s=%.4e\n", kinds[q].name.c_str(), used > 0 ? worst : 1.0);
  }
  std::ofstream csv(dir + "/msd_model.csv");  // for scripts/plot_dispersion.py
  csv << "t";
  for (const auto& kd : kinds) csv << ",model_" << kd.name;
  csv << "\n";
  for (int k = 0; k <= ntau; ++k) {
    csv << k * dtau;
    for (std::size_t q = 0; q < K; ++q) csv << "," << refs[q][static_cast<std::size_t>(k)];
    csv << "\n";
  }
  if (K == 4) {
    const bool ordered = final_msd[0] > final_msd[1] && final_msd[1] > final_msd[2] && final_msd[1] > final_msd[3];
    std::printf("stokes_order=%d\n", ordered ? 1 : 0);
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
    dmax = nan_max(dmax, D);
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

// Particles injected into a uniform stream that moves with them
// (configs/validation/dpm_inlet_stream.yaml): every particle of every
// snapshot keeps the stream's velocity U; the largest |v - U| / |U|, and the
// particles of the last snapshot.
int inlet_stream(const std::string& dir) {
  const auto cfg = load(dir);
  const auto U = cfg.resolved["fluid"]["analytic"]["velocity"].as<std::vector<double>>();
  const double speed = std::sqrt(U[0] * U[0] + U[1] * U[1] + U[2] * U[2]);
  double error = 0.0;
  std::size_t n = 0;
  for (const auto& [step, time] : snapshots(dir, "particles")) {
    const auto v = output::read_dataset(dir + "/particles/" + output::snapshot_name(step), "velocity");
    n = v.size() / 3;
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) error = nan_max(error, std::abs(v[3 * i + k] - U[k]) / speed);
    if (std::any_of(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }))
      throw std::runtime_error("a particle's velocity is not finite in " + dir);
  }
  std::printf("particles=%zu\nspeed_error=%.4e\n", n, error);
  return 0;
}

// The particles of the last snapshot outside the box, and the smallest gap
// between two of them (nearest periodic images) over their mean diameter.
static void inlet_geometry(const std::string& dir, const config::Config& cfg, const std::string& snapshot) {
  const auto x = output::read_dataset(snapshot, "position");
  const auto r = output::read_dataset(snapshot, "radius");
  const auto& d = cfg.resolved["domain"];
  const auto lo = d["lower"].as<std::vector<double>>(), hi = d["upper"].as<std::vector<double>>();
  const auto periodic = d["periodic"].as<std::vector<bool>>();
  long outside = 0;
  double gap = 1e300;
  for (std::size_t i = 0; i < r.size(); ++i) {
    for (int k = 0; k < 3; ++k)
      if (!(x[3 * i + k] >= lo[k] && x[3 * i + k] <= hi[k])) ++outside, k = 3;
    for (std::size_t j = 0; j < i; ++j) {
      double s2 = 0.0;
      for (int k = 0; k < 3; ++k) {
        double e = x[3 * i + k] - x[3 * j + k];
        if (periodic[k]) e -= (hi[k] - lo[k]) * std::round(e / (hi[k] - lo[k]));
        s2 += e * e;
      }
      const double g = (std::sqrt(s2) - r[i] - r[j]) / (r[i] + r[j]);
      if (!(g >= gap)) gap = g;  // a NaN is kept, and fails every bound
    }
  }
  if (r.size() < 2 || x.size() != 3 * r.size())
    throw std::runtime_error("fewer than two particles, or positions not 3 a particle, in " + snapshot);
  std::printf("outside=%ld\nmin_pair_gap=%.6e\n", outside, gap);
}

// An inlet of one fixed-size species (configs/validation/dpm_inlet_blocked.yaml,
// dpm_inlet_periodic.yaml): its particles in the last snapshot (those of its
// diameter), and the mass owed by mass_flow x time (seed 003 eq. 4.18) less
// theirs, in particles; and inlet_geometry's figures.
int inlet_mass(const std::string& dir) {
  const auto cfg = load(dir);
  const auto inj = cfg.resolved["particles"]["injection"][0];
  const auto sp = cfg.resolved["particles"]["species"][inj["species"].as<std::string>()];
  const double D = sp["diameter"].as<double>(), mdot = inj["mass_flow"].as<double>();
  const double m = sp["density"].as<double>() * std::numbers::pi * D * D * D / 6.0;
  const auto last = snapshots(dir, "particles").back();
  const auto rad = output::read_dataset(dir + "/particles/" + output::snapshot_name(last.first), "radius");
  const auto n =
      std::count_if(rad.begin(), rad.end(), [&](double r) { return std::abs(2.0 * r - D) <= 1e-12 * D; });
  std::printf("injected=%ld\nexpected=%.4f\ndeficit_particles=%.4f\n", static_cast<long>(n),
              mdot * last.second / m, mdot * last.second / m - static_cast<double>(n));
  // The particles fly straight along the disk's normal, so each one's
  // distance from the normal through the centre is where it entered: clear
  // of the covering sphere there means at least (D + D_cover) / 2.
  const auto x = output::read_dataset(dir + "/particles/" + output::snapshot_name(last.first), "position");
  const auto c = inj["disk"]["center"].as<std::vector<double>>();
  const auto nrm = inj["disk"]["normal"].as<std::vector<double>>();
  double gap = 1e300;
  for (std::size_t i = 0; i < rad.size(); ++i) {
    if (std::abs(2.0 * rad[i] - D) > 1e-12 * D) continue;
    double d[3], along = 0.0, r2 = 0.0;
    for (int k = 0; k < 3; ++k) along += (d[k] = x[3 * i + k] - c[k]) * nrm[k];
    for (int k = 0; k < 3; ++k) r2 += (d[k] - along * nrm[k]) * (d[k] - along * nrm[k]);
    gap = std::min(gap, std::sqrt(r2));
  }
  if (cfg.resolved["particles"]["species"]["cover"]) {
    const double cover = cfg.resolved["particles"]["species"]["cover"]["diameter"].as<double>();
    std::printf("entry_clearance=%.6f\n", gap / (0.5 * (D + cover)));
  }
  inlet_geometry(dir, cfg, dir + "/particles/" + output::snapshot_name(last.first));
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
    hi = nan_max(hi, r[6]);
    dev = nan_max(dev, std::abs(r[6] - 90.0));
    speed += r[7];
  }
  if (n == 0) throw std::runtime_error("no impact on a mesh wall in " + dir + "/events/impacts.csv");
  std::printf("plate_impacts=%ld\nmean_angle=%.12f\nmin_angle=%.6f\nmax_angle=%.6f\nangle_deviation=%.4e\n"
              "mean_impact_speed=%.6f\n",
              n, sum / n, lo, hi, dev, speed / n);
  return 0;
}

// configs/validation/dpm_pair_into_mesh.yaml: B strikes the resting A at
// 0.05 ms, A reaches the plate (z = 1 mm, its centre at 1.1 mm) at 0.55 ms
// and comes back: at 1 ms A is at z = 1.55 mm moving up at 1 m/s, B at rest
// at 1.8 mm (the reflection laws with e = 1, mu = 0). Errors over D.
int pair_into_mesh(const std::string& dir) {
  const auto snaps = snapshots(dir, "particles");
  const std::string last = dir + "/particles/" + output::snapshot_name(snaps.back().first);
  const auto id = output::read_dataset(last, "id");
  const auto x = output::read_dataset(last, "position");
  const auto v = output::read_dataset(last, "velocity");
  if (id.size() != 2) throw std::runtime_error(fmt::format("{}: {} particles, 2 expected", last, id.size()));
  const double D = 2.0e-4;
  const double want_z[2] = {1.55e-3, 1.8e-3}, want_vz[2] = {1.0, 0.0};
  double position = 0.0, velocity = 0.0;
  for (std::size_t i = 0; i < 2; ++i) {
    const auto k = static_cast<std::size_t>(id[i]);
    position = nan_max({position, std::abs(x[3 * i + 2] - want_z[k]) / D, std::abs(x[3 * i]) / D,
                        std::abs(x[3 * i + 1]) / D});
    velocity =
        nan_max({velocity, std::abs(v[3 * i + 2] - want_vz[k]), std::abs(v[3 * i]), std::abs(v[3 * i + 1])});
  }
  long impacts = 0;
  double time = 0.0;
  for (const auto& r : read_series(dir + "/events/impacts.csv"))  // time,id,wall,x,y,z,angle,speed
    if (r[2] >= 6) {
      ++impacts;
      time = nan_max(time, std::abs(r[0] - 5.5e-4) / 5.5e-4);
    }
  std::printf("position_error=%.4e\nvelocity_error=%.4e\nplate_impacts=%ld\nimpact_time_error=%.4e\n",
              position, velocity, impacts, time);
  return 0;
}

}  // namespace coflow::check
