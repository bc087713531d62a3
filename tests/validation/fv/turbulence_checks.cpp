// coflow-check: the k-epsilon model on fv (issue 22): decaying homogeneous
// turbulence and the decay behind a grid against the model's exact
// solutions, the turbulent channel against DNS and a skin-friction law.
#include <cmath>
#include <limits>

#include "../check/check.hpp"

namespace coflow::check {

namespace {

// A column of series/fluid.csv by name, every row.
std::vector<double> series_column(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  std::stringstream hs(header);
  long index = -1, i = 0;
  for (std::string c; std::getline(hs, c, ','); ++i)
    if (c == name) index = i;
  if (index < 0) throw std::runtime_error(path + " has no column " + name);
  std::vector<double> v;
  for (const auto& row : read_series(path)) v.push_back(row.at(static_cast<std::size_t>(index)));
  return v;
}

// The turbulence parameters with the inlet's k and epsilon those entering
// through x- (the face's own, or turbulence.inlet's; uniform values only:
// the exact decays below start from one k and one epsilon).
fluid::TurbulenceParams inlet_x_minus(const fluid::FluidParams& fp, const config::Config& cfg) {
  fluid::TurbulenceParams t = fp.turbulence;
  const auto in = fp.inlet_turbulence(cfg);
  if (in.varies(0)) throw std::runtime_error("these checks need uniform k and epsilon at the x- inlet");
  t.inlet_k = in.k[0];
  t.inlet_epsilon = in.epsilon[0];
  return t;
}

}  // namespace

// Homogeneous turbulence without mean flow: dk/dt = -epsilon, depsilon/dt =
// -C_e2 epsilon^2 / k, so k = k0 (1 + t / (n tau0))^-n with n = 1 / (C_e2 - 1)
// and tau0 = k0 / epsilon0 (the model's exact solution). The exponent fitted
// over the second half of the run (least squares of ln k against
// ln(t + n tau0)) and the largest error of k.
int ke_decay(const std::string& dir) {
  const auto cfg = load(dir);
  const auto t = fluid_params(cfg).turbulence;
  const double n = 1.0 / (t.constants.C_epsilon2 - 1.0), tau0 = t.initial_k / t.initial_epsilon;
  const std::string path = dir + "/series/fluid.csv";
  const auto time = series_column(path, "time"), k = series_column(path, "k_mean");
  double worst = 0.0, sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0;
  for (std::size_t i = 1; i < time.size(); ++i) {
    const double exact = t.initial_k * std::pow(1.0 + time[i] / (n * tau0), -n);
    worst = nan_max(worst, std::abs(k[i] / exact - 1.0));
    if (!(std::abs(k[i] / exact - 1.0) <= worst)) worst = std::numeric_limits<double>::quiet_NaN();
    if (time[i] < 0.5 * time.back()) continue;
    const double x = std::log(time[i] + n * tau0), y = std::log(k[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y, m += 1;
  }
  const double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  std::printf("decay_exponent=%.6f\nexponent_expected=%.6f\nexponent_error=%.4e\nk_error=%.4e\n", -slope, n,
              std::abs(-slope / n - 1.0), worst);
  return 0;
}

// Uniform flow U along x from an inlet (x- face) carrying k_in, epsilon_in:
// downstream U dk/dx = -epsilon, U depsilon/dx = -C_e2 epsilon^2 / k (no
// production; the turbulent diffusion is O(nu_t / (U x)) ~ 1e-3 here), so k =
// k_in (1 + (C_e2 - 1) epsilon_in x / (U k_in))^-n and epsilon = -U dk/dx.
// The cells' k and epsilon (means across the flow) against it; and, printed
// for the docs, k against Snyder & Lumley's decay law (seed 003 eqs.
// 5.21-5.23, M the cell size as in the seed's case) which the standard
// constants do not follow exactly (they decay as x^-1.087, the experiment as
// x^-1).
int ke_grid(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto t = inlet_x_minus(fp, cfg);
  const auto& d = cfg.domain;
  const double h = d.spacing()[0], U = fp.boundary(0, cfg).value.values.at(0);
  const double c2 = t.constants.C_epsilon2, n = 1.0 / (c2 - 1.0);
  const std::string snap = last_snapshot(dir);
  std::vector<std::size_t> dims;
  const auto k = output::read_dataset(snap, "k", &dims), eps = output::read_dataset(snap, "epsilon");
  const long nx = static_cast<long>(dims[2]), across = static_cast<long>(dims[0] * dims[1]);
  const fluid::GridDecay sl{U, h};
  const double xi0 = d.lower[0] / h;  // the inlet's x / M (the grid at x = 0)
  double worst_k = 0, worst_e = 0, sl_dev = 0;
  for (long i = 0; i < nx; ++i) {
    double km = 0, em = 0;
    for (long a = 0; a < across; ++a) km += k[static_cast<std::size_t>(a * nx + i)], em += eps[static_cast<std::size_t>(a * nx + i)];
    km /= static_cast<double>(across), em /= static_cast<double>(across);
    const double x = (i + 0.5) * h;
    const double base = 1.0 + (c2 - 1.0) * t.inlet_epsilon * x / (U * t.inlet_k);
    const double ke = t.inlet_k * std::pow(base, -n), ee = t.inlet_epsilon * std::pow(base, -n - 1.0);
    const double ek = std::abs(km / ke - 1.0), ee_rel = std::abs(em / ee - 1.0);
    worst_k = nan_max(worst_k, ek);  // NaN sticks
    worst_e = nan_max(worst_e, ee_rel);
    if (!(ek == ek)) worst_k = ek;
    if (!(ee_rel == ee_rel)) worst_e = ee_rel;
    sl_dev = nan_max(sl_dev, std::abs(km / sl.k(xi0 + i + 0.5) - 1.0));
  }
  std::printf("k_error=%.4e\nepsilon_error=%.4e\nsnyder_lumley_deviation=%.4e\n", worst_k, worst_e, sl_dev);
  return 0;
}

// The same on fv's adaptive grid, from the composite grid's own cells (the
// last snapshot's <stem>_levels.h5: each level's cells, their corner nodes
// and values): every leaf cell's k and epsilon against the exact decay at
// its centre (the uniform view shows a coarse cell's value over its fine
// cells, whose centres lie half a fine cell off).
int ke_grid_levels(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto t = inlet_x_minus(fp, cfg);
  const double U = fp.boundary(0, cfg).value.values.at(0), c2 = t.constants.C_epsilon2, n = 1.0 / (c2 - 1.0);
  std::string snap = last_snapshot(dir);
  snap = snap.substr(0, snap.size() - 3) + "_levels.h5";
  double worst_k = 0, worst_e = 0;
  long cells = 0;
  for (int level = 0; output::has_dataset(snap, "level" + std::to_string(level) + "_cells"); ++level) {
    const std::string p = "level" + std::to_string(level) + "_";
    std::vector<std::size_t> shape;
    const auto corners = output::read_dataset(snap, p + "cells", &shape),
               nodes = output::read_dataset(snap, p + "nodes");
    const auto k = output::read_dataset(snap, p + "k"), eps = output::read_dataset(snap, p + "epsilon");
    const std::size_t per = shape.at(1);
    for (std::size_t c = 0; c < k.size(); ++c, ++cells) {
      double x = 0.0;
      for (std::size_t j = 0; j < per; ++j) x += nodes.at(3 * static_cast<std::size_t>(corners[c * per + j]));
      x = x / static_cast<double>(per) - cfg.domain.lower[0];
      const double base = 1.0 + (c2 - 1.0) * t.inlet_epsilon * x / (U * t.inlet_k);
      const double ek = std::abs(k[c] / (t.inlet_k * std::pow(base, -n)) - 1.0);
      const double ee = std::abs(eps[c] / (t.inlet_epsilon * std::pow(base, -n - 1.0)) - 1.0);
      worst_k = nan_max(worst_k, ek);  // NaN sticks
      worst_e = nan_max(worst_e, ee);
      if (!(ek == ek)) worst_k = ek;
      if (!(ee == ee)) worst_e = ee;
    }
  }
  if (cells == 0) throw std::runtime_error(snap + " holds no level");
  std::printf("cells=%ld\nk_error=%.4e\nepsilon_error=%.4e\n", cells, worst_k, worst_e);
  return 0;
}

// Moser, Kim & Mansour 1999 (Phys. Fluids 11:943), DNS of channel flow at
// Re_tau = 392.24: the mean velocity U+ at y+ (file chan395.means, rows as
// published; tests/validation/references.csv names the copy read).
struct MkmRow {
  double y_plus, u_plus;
};
const MkmRow kMkm395[] = {{29.858, 13.479}, {39.744, 14.290}, {50.958, 14.902}, {68.804, 15.614},
                          {98.400, 16.493}, {150.92, 17.664}, {198.91, 18.535}, {251.08, 19.256},
                          {301.61, 19.758}};

// A force-driven channel between walls at y- and y+ (half height delta), steady:
// u_tau = sqrt(f delta / rho) (the force balance). u+ (the mean over x and over
// the two halves) against MKM's at y+ 30-300, linear between the cell centres
// (the DNS's points below the first cell centre, as with wall functions, not
// compared; NaN with fewer than 5 of the 9 points);
// the skin friction Cf = 2 / U_b+^2 against Dean's (1978) 0.073 Re_b^-1/4,
// Re_b = U_b 2 delta / nu.
int ke_channel(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const double delta = 0.5 * (d.upper[1] - d.lower[1]), dy = d.spacing()[1];
  const double utau = std::sqrt(fp.body_force[0] * delta / fp.density), nu = fp.viscosity;
  std::vector<std::size_t> dims;
  const auto u = output::read_dataset(last_snapshot(dir), "velocity", &dims);
  const long ny = static_cast<long>(dims[1]), nx = static_cast<long>(dims[2]);
  std::vector<double> prof(static_cast<std::size_t>(ny), 0.0);  // mean u over x
  double bulk = 0.0;
  for (long j = 0; j < ny; ++j) {
    for (long i = 0; i < nx; ++i) prof[static_cast<std::size_t>(j)] += u[static_cast<std::size_t>((j * nx + i) * 3)];
    prof[static_cast<std::size_t>(j)] /= static_cast<double>(nx);
    bulk += prof[static_cast<std::size_t>(j)] / static_cast<double>(ny);
  }
  // The two halves' mean, linear between centres (yp from the first centre to the middle).
  auto u_plus_at = [&](double yp) {
    const double x = yp * nu / utau / dy - 0.5;
    const long j = std::clamp(static_cast<long>(std::floor(x)), 0L, ny / 2 - 2);
    const double w = x - static_cast<double>(j);
    auto half = [&](long m) {
      return 0.5 * (prof[static_cast<std::size_t>(m)] + prof[static_cast<std::size_t>(ny - 1 - m)]);
    };
    return ((1 - w) * half(j) + w * half(j + 1)) / utau;
  };
  if (ny < 4) throw std::runtime_error("ke_channel needs at least 4 cells across the channel");
  double worst = 0.0;
  int compared = 0;
  const double first = 0.5 * dy * utau / nu;  // y+ of the first cell centre
  for (const auto& r : kMkm395) {
    if (r.y_plus < first) {  // wall functions: the law itself below the first centre, not compared
      std::printf("y+ %7.2f: below the first cell centre (y+ %.2f), not compared\n", r.y_plus, first);
      continue;
    }
    ++compared;
    const double e = std::abs(u_plus_at(r.y_plus) / r.u_plus - 1.0);
    std::printf("y+ %7.2f: u+ %.4f (DNS %.3f, %+.2f %%)\n", r.y_plus, u_plus_at(r.y_plus), r.u_plus,
                100 * (u_plus_at(r.y_plus) / r.u_plus - 1.0));
    worst = std::isnan(worst) || e <= worst ? worst : e;  // a NaN sticks
  }
  if (compared < 5) worst = std::numeric_limits<double>::quiet_NaN();  // too few of the DNS's points to judge
  std::printf("u_plus_points=%d\n", compared);
  const double ub = bulk / utau, cf = 2.0 / (ub * ub), re_b = bulk * 2 * delta / nu;
  const double dean = 0.073 * std::pow(re_b, -0.25);
  std::printf("re_tau=%.3f\nbulk_u_plus=%.4f\nu_plus_error=%.4e\ncf=%.5e\ncf_dean=%.5e\ncf_error=%.4e\n",
              utau * delta / nu, ub, worst, cf, dean, std::abs(cf / dean - 1.0));
  return 0;
}

// A backward-facing step at x = domain.lower (the step's edge; the floor
// behind it the y- wall; the step's height a ninth of the box's, Driver &
// Seegmiller's expansion ratio 1.125): the reattachment length x_r / H,
// where the velocity along x of the floor's first cells turns from upstream
// to downstream for the last time (linear between cell centres; the mean
// over z), against Driver & Seegmiller's 6.26 (1985; NASA Turbulence
// Modeling Resource, 2DBFS: 6.26 +/- 0.10); NaN where the flow never
// separates or never reattaches. Also floor_k_20h, k of the floor's first
// cells at x = 20 H (what the wall functions set there), for the comparison
// with OpenFOAM (scripts/openfoam_backward_step.sh).
int ke_backward_step(const std::string& dir) {
  const auto cfg = load(dir);
  const auto& d = cfg.domain;
  const double height = (d.upper[1] - d.lower[1]) / 9.0;
  const double dx = d.spacing()[0];
  std::vector<std::size_t> dims;
  const auto u = output::read_dataset(last_snapshot(dir), "velocity", &dims);
  const long nz = static_cast<long>(dims[0]), ny = static_cast<long>(dims[1]),
             nx = static_cast<long>(dims[2]);
  // The floor's first cells along x (the mean over z) of component 0 of a
  // field of `comps` values per cell.
  auto floor_row = [&](const std::vector<double>& f, std::size_t comps) {
    if (f.size() != static_cast<std::size_t>(nz * ny * nx) * comps)
      throw std::runtime_error("ke_backward_step: the snapshot's fields differ in shape");
    std::vector<double> row(static_cast<std::size_t>(nx), 0.0);
    for (long z = 0; z < nz; ++z)
      for (long i = 0; i < nx; ++i)
        row[static_cast<std::size_t>(i)] +=
            f[static_cast<std::size_t>((z * ny) * nx + i) * comps] / static_cast<double>(nz);
    return row;
  };
  const auto floor = floor_row(u, 3);
  require_finite(floor, "ke_backward_step: the floor cells' u");
  double xr = std::numeric_limits<double>::quiet_NaN(), umin = 0.0;
  for (long i = 0; i + 1 < nx; ++i) {
    const double a = floor[static_cast<std::size_t>(i)], b = floor[static_cast<std::size_t>(i + 1)];
    umin = std::min(umin, a);
    if (a < 0.0 && b >= 0.0) xr = (static_cast<double>(i) + 0.5 + a / (a - b)) * dx;  // the last crossing
  }
  // k of the floor's first cells at x = 20 H (linear between cell centres):
  // where the wall function sets the wall cells' k.
  const auto floor_k = floor_row(output::read_dataset(last_snapshot(dir), "k"), 1);
  require_finite(floor_k, "ke_backward_step: the floor cells' k");
  const double at = 20.0 * height / dx - 0.5, w = at - std::floor(at);
  const auto i0 = static_cast<std::size_t>(std::max(0.0, std::floor(at)));
  const double k20 = i0 + 1 < floor_k.size() ? (1.0 - w) * floor_k[i0] + w * floor_k[i0 + 1]
                                             : std::numeric_limits<double>::quiet_NaN();
  const double ref = 6.26;
  std::printf("floor_u_min=%.4f\nx_r_over_h=%.4f\nx_r_reference=%.2f\nx_r_error=%.4e\nfloor_k_20h=%.6e\n",
              umin, xr / height, ref, std::abs(xr / height / ref - 1.0), k20);
  return 0;
}

}  // namespace coflow::check
