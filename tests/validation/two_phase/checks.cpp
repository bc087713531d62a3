// coflow-check: two fluids by the colour-gradient model (seed 000 §2.3.4) and
// interior solids: Laplace's law at a static droplet, the contact angle of a
// droplet on a wall, layered flow between plates with its relative
// permeabilities, each colour's mass, and the permeability of a voxelised
// sphere array.
#include "../check/check.hpp"
#include "capillary_bridge.hpp"

namespace coflow::check {

namespace {

struct Snapshot {
  std::vector<double> phase, pressure, velocity;
  long nx = 0, ny = 0, nz = 0;
};

Snapshot read_last(const std::string& dir) {
  Snapshot s;
  std::vector<std::size_t> dims;
  const std::string f = last_snapshot(dir);
  s.phase = output::read_dataset(f, "phase", &dims);
  s.nz = static_cast<long>(dims[0]), s.ny = static_cast<long>(dims[1]), s.nx = static_cast<long>(dims[2]);
  s.pressure = output::read_dataset(f, "pressure");
  s.velocity = output::read_dataset(f, "velocity");
  return s;
}

// The slope of the least-squares line through the points (t, y).
struct LineFit {
  double n = 0, st = 0, sy = 0, stt = 0, sty = 0;
  void add(double t, double y) { n += 1, st += t, sy += y, stt += t * t, sty += t * y; }
  double slope() const { return (n * sty - st * sy) / (n * stt - st * st); }
};

// The largest relative change of each colour's mass over the series' rows.
double colour_mass_drift(const std::string& dir) {
  const auto rows = read_series(dir + "/series/fluid.csv");
  if (rows.size() < 2)
    throw std::runtime_error("colour mass: fewer than 2 rows in series/fluid.csv: nothing to compare");
  double worst = 0.0;
  for (const auto& r : rows)
    for (int c : {8, 9}) {  // mass_red, mass_blue
      const double d = std::abs(r.at(c) - rows.front().at(c)) / rows.front().at(c);
      worst = std::isnan(d) ? d : std::max(worst, d);
    }
  return worst;
}

}  // namespace

// A static droplet (the last painted sphere) in a periodic box: its radius
// from the red volume (area in 2D), the pressure jump between the mean
// pressure inside (r < R - 5 dx) and outside (r > R + 5 dx), against Laplace's
// gamma / R (2D) or 2 gamma / R (3D). Spurious currents as the capillary
// number of the largest speed, mu |u|max / gamma.
int laplace(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const double dx = d.spacing()[0];
  const auto s = read_last(dir);
  require_finite(s.phase, dir + ": the phase field");
  const bool d3 = s.nz > 1;
  const auto& drop = fp.initial_phase.back();
  double red = 0.0;
  for (double p : s.phase) red += 0.5 * (1.0 + p);
  const double R =
      d3 ? std::cbrt(3.0 * red / (4.0 * std::numbers::pi)) * dx : std::sqrt(red / std::numbers::pi) * dx;
  double pin = 0.0, pout = 0.0, nin = 0.0, nout = 0.0, umax = 0.0;
  for (long k = 0; k < s.nz; ++k)
    for (long j = 0; j < s.ny; ++j)
      for (long i = 0; i < s.nx; ++i) {
        const double x[3] = {d.lower[0] + (i + 0.5) * dx, d.lower[1] + (j + 0.5) * dx,
                             d.lower[2] + (k + 0.5) * dx};
        double r2 = 0.0;
        for (int a = 0; a < (d3 ? 3 : 2); ++a) {
          const double L = d.upper[a] - d.lower[a];
          double dd = std::abs(x[a] - drop.centre.values[a]);
          dd = std::min(dd, L - dd);  // periodic image
          r2 += dd * dd;
        }
        const long c = (k * s.ny + j) * s.nx + i;
        const double r = std::sqrt(r2);
        if (r < R - 5 * dx) pin += s.pressure[c], nin += 1;
        if (r > R + 5 * dx) pout += s.pressure[c], nout += 1;
        const double* u = &s.velocity[3 * c];
        umax = nan_max(umax, std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
      }
  const double gamma = fp.two_phase.surface_tension, dp = pin / nin - pout / nout;
  const double laplace_dp = (d3 ? 2.0 : 1.0) * gamma / R;
  std::printf("surface_tension=%.9e\ndimensions=%d\n", gamma, d3 ? 3 : 2);
  std::printf(
      "radius=%.9e\npressure_jump=%.9e\nlaplace_error=%.6e\nspurious_capillary=%.6e\ncolour_mass_drift=%."
      "6e\n",
      R, dp, std::abs(dp / laplace_dp - 1.0), fp.density * fp.viscosity * umax / gamma,
      colour_mass_drift(dir));
  return 0;
}

// A red droplet on the wall y- of a 2D box: the points of the phase = 0
// contour (linear interpolation between neighbouring cell centres) more than
// three cells from the wall, a circle fitted to them by least squares (Kåsa
// 1976: x^2 + y^2 = 2 a x + 2 b y + c), and the angle at which that circle
// meets the wall, inside the drop: cos(theta) = (y_wall - b) / R.
int contact_angle(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const double dx = d.spacing()[0];
  const auto s = read_last(dir);
  require_finite(s.phase, dir + ": the phase field");
  std::vector<std::array<double, 2>> pts;
  const auto at = [&](long i, long j) { return s.phase[j * s.nx + i]; };
  for (long j = 0; j < s.ny; ++j)
    for (long i = 0; i < s.nx; ++i) {
      const double p = at(i, j);
      if (i + 1 < s.nx && p * at(i + 1, j) < 0) pts.push_back({i + 0.5 + p / (p - at(i + 1, j)), j + 0.5});
      if (j + 1 < s.ny && p * at(i, j + 1) < 0) pts.push_back({i + 0.5, j + 0.5 + p / (p - at(i, j + 1))});
    }
  double m[3][4] = {};  // normal equations of the Kåsa fit, in cells
  long used = 0;
  for (const auto& q : pts) {
    if (q[1] <= 3.0) continue;
    const double row[3] = {2 * q[0], 2 * q[1], 1.0}, rhs = q[0] * q[0] + q[1] * q[1];
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) m[a][b] += row[a] * row[b];
      m[a][3] += row[a] * rhs;
    }
    ++used;
  }
  if (used < 10)
    throw std::runtime_error(fmt::format("{}: only {} interface points away from the wall", dir, used));
  for (int a = 0; a < 3; ++a)  // Gauss-Jordan on the 3 x 4 system
    for (int b = 0; b < 3; ++b)
      if (b != a) {
        const double f = m[b][a] / m[a][a];
        for (int c = 0; c < 4; ++c) m[b][c] -= f * m[a][c];
      }
  const double xc = m[0][3] / m[0][0], yc = m[1][3] / m[1][1], c = m[2][3] / m[2][2];
  const double R = std::sqrt(c + xc * xc + yc * yc);
  const double theta = std::acos(std::clamp(-yc / R, -1.0, 1.0)) * 180.0 / std::numbers::pi;
  std::printf("interface_points=%ld\ndrop_radius=%.6e\ncontact_angle=%.4f\nangle_error=%.4f\n", used, R * dx,
              theta, std::abs(theta - fp.two_phase.contact_angle));
  std::printf("colour_mass_drift=%.6e\n", colour_mass_drift(dir));
  return 0;
}

// Layered co-current flow between walls at y = 0 and H, driven by a body
// force G along x: red in the core |y - H/2| < a, blue along the walls
// (Yiotis, Psihogios, Kainourgiakis, Papaioannou & Stubos 2007; derived here
// again from the piecewise Poiseuille profile). With M =
// mu_red / mu_blue, b = H/2, s = a/b = the red saturation:
//   blue: u = G (b^2 - y^2) / (2 mu_b);  red: u = G (a^2 - y^2) / (2 mu_r) + G (b^2 - a^2) / (2 mu_b),
//   kr_blue = 1 - 3 s / 2 + s^3 / 2,  kr_red = s^3 + 3 M s (1 - s^2) / 2,
// each phase's flow rate over that of the channel full of it, G H^3 / (12 mu).
int layered(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const auto h = d.spacing();
  const double G = fp.body_force[0], H = d.upper[1] - d.lower[1], b = 0.5 * H, dz = d.upper[2] - d.lower[2];
  const double mu_r = fp.density * fp.viscosity, mu_b = fp.density * fp.two_phase.viscosity_blue,
               M = mu_r / mu_b;
  const auto last = read_series(dir + "/series/fluid.csv").back();
  const double sat = last.at(10), a = sat * b;
  const auto snap = read_last(dir);
  double err2 = 0.0, ref2 = 0.0;
  for (long j = 0; j < snap.ny; ++j) {
    const double y = std::abs((j + 0.5) * h[1] - b);
    const double ua = y >= a ? G * (b * b - y * y) / (2 * mu_b)
                             : G * (a * a - y * y) / (2 * mu_r) + G * (b * b - a * a) / (2 * mu_b);
    for (long i = 0; i < snap.nx; ++i) {
      const double un = snap.velocity[3 * (j * snap.nx + i)];
      err2 += (un - ua) * (un - ua);
      ref2 += ua * ua;
    }
  }
  const double kr_b = 1.0 - 1.5 * sat + 0.5 * sat * sat * sat,
               kr_r = sat * sat * sat + 1.5 * M * sat * (1.0 - sat * sat);
  const double q_r = G * H * H * H * dz / (12 * mu_r), q_b = G * H * H * H * dz / (12 * mu_b);
  std::printf("saturation_red=%.6f\nviscosity_ratio=%.4f\nprofile_l2_error=%.6e\n", sat, M,
              std::sqrt(err2 / ref2));
  std::printf("kr_red=%.6f\nkr_red_analytic=%.6f\nkr_red_error=%.6e\n", last.at(11) / q_r, kr_r,
              std::abs(last.at(11) / q_r / kr_r - 1.0));
  std::printf("kr_blue=%.6f\nkr_blue_analytic=%.6f\nkr_blue_error=%.6e\n", last.at(14) / q_b, kr_b,
              std::abs(last.at(14) / q_b / kr_b - 1.0));
  std::printf("colour_mass_drift=%.6e\n", colour_mass_drift(dir));
  return 0;
}

// Stokes flow through a simple cubic array of spheres, one voxelised sphere
// (fluid.solids) in a periodic box driven by a body force f on the fluid.
// The fluid's velocity is that of a mean pressure gradient G = f, under which
// the force on a sphere is G L^3 (the fluid's share f V_f plus G V_s on the
// sphere's volume), so Zick & Homsy's K = f L^3 / (6 pi mu a U), U the
// superficial velocity (the box's mean) and a the radius of the voxels'
// volume; against their table at the voxels' solid fraction (within 1 % of a
// row).
int permeability(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const double dx = d.spacing()[0];
  std::vector<std::size_t> dims;
  const std::string f = last_snapshot(dir);
  const auto solid = output::read_dataset(f, "solid_fraction", &dims);
  const auto u = output::read_dataset(f, "velocity");
  double n_solid = 0.0, sum_u = 0.0;
  for (std::size_t c = 0; c < solid.size(); ++c) n_solid += solid[c], sum_u += u[3 * c];
  const double n = static_cast<double>(solid.size()), phi = n_solid / n;
  const double a = std::cbrt(3.0 * n_solid / (4.0 * std::numbers::pi)) * dx, U = sum_u / n;
  const double mu = fp.density * fp.viscosity, F = fp.body_force[0] * n * dx * dx * dx;
  const double K = F / (6.0 * std::numbers::pi * mu * a * U);
  // Zick & Homsy (1982), J. Fluid Mech. 115, 13, Table 2 (simple cubic).
  const double table[][2] = {{0.027, 2.008}, {0.064, 2.810}, {0.125, 4.292}, {0.216, 7.442}, {0.343, 15.4}};
  double ref = 0.0;
  for (const auto& row : table)
    if (std::abs(phi / row[0] - 1.0) < 0.01) ref = row[1];
  const auto rows = read_series(dir + "/series/fluid.csv");
  const double m_end = rows.back().at(2), m_before = rows.at(rows.size() * 4 / 5).at(2);
  std::printf("phi=%.5f\nreynolds=%.3e\nK=%.12e\nsettling=%.3e\n", phi, U * 2 * a / fp.viscosity, K,
              std::abs(m_end / m_before - 1.0));
  if (ref > 0.0) std::printf("K_zick_homsy=%.3f\nK_error=%.6e\n", ref, std::abs(K / ref - 1.0));
  return 0;
}

// Capillary filling of a slit between the two plates fluid.solids[0] (below)
// and [1] (above), red entering at the plates' left end: in each snapshot the
// meniscus on the gap's centreline (phase = 0 between cell centres), l its
// distance into the slit; Washburn's law with both fluids' Poiseuille
// resistance in the slit of length L, X(l) = mu_r l^2 / 2 + mu_b (L l - l^2 / 2)
// = gamma H cos(theta) t / 6 + const, fitted (least squares) over the
// snapshots with l in [L/2, 0.9 L], after the entrance transient.
int washburn(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const auto h = d.spacing();
  const auto& below = fp.solids.at(0);
  const auto& above = fp.solids.at(1);
  const double x0 = below.lower.values[0], L = below.upper.values[0] - x0;
  const double H = above.lower.values[1] - below.upper.values[1];
  const double yc = below.upper.values[1] + 0.5 * H;
  const long j0 = std::lround((yc - d.lower[1]) / h[1]) - 1;  // the two rows about the centreline
  const double mu_r = fp.density * fp.viscosity, mu_b = fp.density * fp.two_phase.viscosity_blue;
  const double theta =
      (below.contact_angle < 0 ? fp.two_phase.contact_angle : below.contact_angle) * std::numbers::pi / 180.0;
  LineFit fit;
  long used = 0;
  for (const auto& [index, t] : snapshots(dir, "fluid")) {
    std::vector<std::size_t> dims;
    const auto phase = output::read_dataset(dir + "/fluid/" + output::snapshot_name(index), "phase", &dims);
    const long nx = static_cast<long>(dims[2]);
    const auto centre = [&](long i) { return 0.5 * (phase[j0 * nx + i] + phase[(j0 + 1) * nx + i]); };
    const long i0 = std::lround((x0 - d.lower[0]) / h[0]), i1 = i0 + std::lround(L / h[0]);
    double xm = -1.0;
    for (long i = i0 + 1; i < i1 && xm < 0; ++i)
      if (centre(i - 1) >= 0.0 && centre(i) < 0.0)
        xm = d.lower[0] + (i - 0.5 + centre(i - 1) / (centre(i - 1) - centre(i))) * h[0];
    const double l = xm - x0;
    if (xm < 0 || l < 0.5 * L || l > 0.9 * L) continue;
    const double X = mu_r * l * l / 2 + mu_b * (L * l - l * l / 2);
    fit.add(t, X);
    ++used;
  }
  if (used < 5)
    throw std::runtime_error(fmt::format("{}: the meniscus is in [L/2, 0.9 L] in {} snapshots", dir, used));
  const double slope = fit.slope();
  const double washburn = fp.two_phase.surface_tension * H * std::cos(theta) / 6.0;
  std::printf("snapshots=%ld\nslope=%.6e\nwashburn_slope=%.6e\nwashburn_error=%.6e\n", used, slope, washburn,
              std::abs(slope / washburn - 1.0));
  std::printf("colour_mass_drift=%.6e\n", colour_mass_drift(dir));
  return 0;
}

// Red injected through the velocity face x- (phase red): from a fifth of the
// run on, the red mass grows at rho U A (A the face's area), the inlet's
// mass flux; the least-squares rate over the series' rows against it.
int injection_phase(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const auto& d = cfg.domain;
  const double U = fp.boundary(0, cfg).value.values.at(0);
  const double A = (d.upper[1] - d.lower[1]) * (d.upper[2] - d.lower[2]);
  const auto rows = read_series(dir + "/series/fluid.csv");
  LineFit fit;
  for (std::size_t r = rows.size() / 5; r < rows.size(); ++r) fit.add(rows[r].at(0), rows[r].at(8));
  const double rate = fit.slope(), expected = fp.density * U * A;
  std::printf("red_mass_rate=%.9e\ninlet_flux=%.9e\nred_rate_error=%.6e\n", rate, expected,
              std::abs(rate / expected - 1.0));
  return 0;
}

// A grain (the one particle, free) at the top of a red layer in a periodic
// box (configs/validation/two_phase_grain_interface.yaml): the red-to-blue
// crossing of the phase upwards, in each column more than two radii from the
// grain's axis, averaged; its height over the grain's centre (the last
// particle snapshot),
// in cells, against a cos(theta) (a flat interface meets a sphere at theta
// there: the red fluid below it climbs a grain it wets).
int grain_interface(const std::string& dir) {
  const auto cfg = load(dir);
  const auto& d = cfg.domain;
  const double dx = d.spacing()[0];
  const YAML::Node part = cfg.resolved["particles"];
  const YAML::Node grain = part["initial"][0]["single"];
  const YAML::Node species = part["species"][grain["species"].as<std::string>()];
  const double a = 0.5 * species["diameter"].as<double>() / dx;
  double theta = species["contact_angle"].as<double>();
  if (theta < 0.0) theta = cfg.resolved["fluid"]["two_phase"]["contact_angle"].as<double>();
  // The grain's centre in the last particle snapshot (a free grain moves).
  const auto centre = output::read_dataset(last_snapshot(dir, "particles"), "position");
  double c[3];
  for (int k = 0; k < 3; ++k) c[k] = (centre.at(k) - d.lower[k]) / dx - 0.5;  // in cell-centre units
  const auto s = read_last(dir);
  require_finite(s.phase, dir + ": the phase field");
  double sum = 0.0;
  long columns = 0;
  for (long j = 0; j < s.ny; ++j)
    for (long i = 0; i < s.nx; ++i) {
      double dxy[2] = {std::abs(i - c[0]), std::abs(j - c[1])};
      dxy[0] = std::min(dxy[0], s.nx - dxy[0]), dxy[1] = std::min(dxy[1], s.ny - dxy[1]);
      if (std::hypot(dxy[0], dxy[1]) <= 2.0 * a) continue;
      for (long k = 0; k + 1 < s.nz; ++k) {
        const double p = s.phase[(k * s.ny + j) * s.nx + i], q = s.phase[((k + 1) * s.ny + j) * s.nx + i];
        if (p > 0.0 && q <= 0.0) sum += k + p / (p - q), ++columns;
      }
    }
  if (columns == 0) throw std::runtime_error(dir + ": no red-to-blue crossing away from the grain");
  const double offset = sum / columns - c[2], expected = a * std::cos(theta * std::numbers::pi / 180.0);
  std::printf("columns=%ld\ncontact_angle=%.4f\nheight_offset=%.6f\nexpected_offset=%.6f\noffset_error=%.6f\n",
              columns, theta, offset, expected, std::abs(offset - expected));
  std::printf("colour_mass_drift=%.6e\n", colour_mass_drift(dir));
  return 0;
}

// The red volume of the last fluid snapshot, in cells: sum of (1 + phase)/2
// times the fluid share (1 - solid_fraction; interior solids 0).
double red_volume_cells(const std::string& dir) {
  const std::string f = last_snapshot(dir);
  const auto phase = output::read_dataset(f, "phase"), solid = output::read_dataset(f, "solid_fraction");
  double v = 0.0;
  for (std::size_t c = 0; c < phase.size(); ++c) v += 0.5 * (1.0 + phase[c]) * (1.0 - solid.at(c));
  return v;
}

// A capillary bridge between a fixed grain (the first particle) and a
// sphere of the same radius touching it on its -x side: the grain's force
// along x in series/immersed.csv, averaged over the last quarter of the run,
// against the exact bridge of the run's red volume between touching spheres
// at the contact angle (capillary_bridge.hpp: Young-Laplace's meridian; it
// tends to the small-bridge limit 2 pi R gamma cos(theta) of Willett et al.
// 2000 as the volume goes to 0; the bridge pulls the spheres together, so
// the grain's force is -F). Also printed: the force over that limit.
int bridge(const std::string& dir) {
  const auto cfg = load(dir);
  const auto fp = fluid_params(cfg);
  const double dx = cfg.domain.spacing()[0], gamma = fp.two_phase.surface_tension;
  const YAML::Node part = cfg.resolved["particles"];
  const YAML::Node grain = part["initial"][0]["single"];
  const YAML::Node species = part["species"][grain["species"].as<std::string>()];
  const double R = 0.5 * species["diameter"].as<double>();
  double theta = species["contact_angle"].as<double>();
  if (theta < 0.0) theta = fp.two_phase.contact_angle;
  theta *= std::numbers::pi / 180.0;
  const auto rows = read_series(dir + "/series/immersed.csv");
  const double t_end = rows.back().at(0);
  double sum = 0.0, lo = 1e300, hi = -1e300;
  long n = 0;
  for (const auto& r : rows)
    if (r.at(0) >= 0.75 * t_end) sum += r.at(1), lo = std::min(lo, r.at(1)), hi = nan_max(hi, r.at(1)), ++n;
  if (n == 0) throw std::runtime_error(dir + ": no rows in the last quarter");
  const double F = -sum / n, limit = 2.0 * std::numbers::pi * R * gamma * std::cos(theta);
  const double volume = red_volume_cells(dir);
  const BridgeShape exact = capillary_bridge(R / dx, theta, volume);
  const double expected = exact.force * gamma * dx;
  std::printf("bridge_force=%.6e\nred_volume_cells=%.3f\nfilling_angle_deg=%.3f\ntheory_force=%.6e\n", F,
              volume, exact.filling * 180.0 / std::numbers::pi, expected);
  std::printf("small_bridge_limit=%.6e\nlimit_ratio=%.6f\ntheory_ratio=%.6f\n", limit, F / limit,
              expected / limit);
  std::printf("bridge_error=%.6e\nforce_spread=%.6e\n", std::abs(F / expected - 1.0), (hi - lo) / expected);
  std::printf("colour_mass_drift=%.6e\n", colour_mass_drift(dir));
  return 0;
}

// The colour masses alone (any two-phase run).
int colour_mass(const std::string& dir) {
  std::printf("colour_mass_drift=%.6e\n", colour_mass_drift(dir));
  return 0;
}

}  // namespace coflow::check
