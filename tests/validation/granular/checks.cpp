// coflow-check: soft-sphere DEM: two-sphere impact and gravity pour.
#include <filesystem>

#include "../check/check.hpp"

namespace coflow::check {

// dpm's wall impacts (events/impacts.csv) against the series' wall
// collisions: the same count, and none at a symmetry face (a mirror).
static void impacts(const std::string& dir, const config::Config& cfg,
                    const std::vector<std::vector<double>>& p) {
  const char* faces[] = {"x-", "x+", "y-", "y+", "z-", "z+"};
  const YAML::Node b = cfg.resolved["particles"]["boundaries"];
  double counted = 0.0;
  for (std::size_t r = 1; r < p.size(); ++r) counted += p[r][7];
  const auto rows = read_series(dir + "/events/impacts.csv");
  long mirrors = 0;
  for (const auto& row : rows) {
    const int wall = static_cast<int>(row[2]);
    if (wall >= 0 && wall < 6 && b && b[faces[wall]] && b[faces[wall]].Scalar() == "symmetry") ++mirrors;
  }
  // The mirrors' momentum (their faces' columns of walls.csv, summed over the
  // rows): nonzero where particles reached a symmetry face, so that
  // mirror_impacts = 0 says something.
  const auto w = read_series(dir + "/series/walls.csv");
  std::ifstream in(dir + "/series/walls.csv");
  std::string header;
  std::getline(in, header);
  double mirrored = 0.0;
  std::stringstream names(header);
  std::size_t col = 0;
  for (std::string name; std::getline(names, name, ','); ++col)
    for (int f = 0; f < 6; ++f)
      if (b && b[faces[f]] && b[faces[f]].Scalar() == "symmetry" &&
          name.rfind(std::string(faces[f]) + "_f", 0) == 0)
        for (const auto& row : w) mirrored += std::abs(row[col]);
  std::printf("impacts=%zu\nimpacts_vs_wall_collisions=%.1f\nmirror_impacts=%ld\nmirror_load=%.6e\n",
              rows.size(), std::abs(static_cast<double>(rows.size()) - counted), mirrors, mirrored);
}

// Grains of one species in a closed box under gravity, no fluid: between two
// series rows the particles' momentum changes by M g dt minus the impulse they
// give the walls (series/walls.csv, mean force x dt); contacts between grains
// cancel. The largest residual of any component over all intervals, relative
// to the weight's impulse M |g| dt.
int walls(const std::string& dir) {
  const auto cfg = load(dir);
  const YAML::Node sp = cfg.resolved["particles"]["species"].begin()->second;
  const double d = std::stod(sp["diameter"].Scalar()), rho = std::stod(sp["density"].Scalar());
  const double m = rho * std::numbers::pi * d * d * d / 6.0;
  const auto p = read_series(dir + "/series/particles.csv");
  const auto w = read_series(dir + "/series/walls.csv");
  if (p.size() != w.size() || p.size() < 2) throw std::runtime_error("particles.csv and walls.csv rows differ");
  const auto& g = cfg.gravity;
  double worst = 0.0;
  for (std::size_t r = 1; r < p.size(); ++r) {
    const double dt = w[r][0] - w[r - 1][0], M = m * p[r][1];
    for (int q = 0; q < 3; ++q) {
      double on_walls = 0.0;
      for (std::size_t c = 1 + q; c < w[r].size(); c += 3) on_walls += w[r][c];
      const double residual = (p[r][2 + q] - p[r - 1][2 + q]) - (M * g[q] - on_walls) * dt;
      const double rel = std::abs(residual) / (M * std::hypot(g[0], g[1], g[2]) * dt);
      worst = std::isnan(rel) ? rel : std::max(worst, rel);
    }
  }
  std::printf("momentum_balance=%.6e\n", worst);
  if (std::filesystem::exists(dir + "/events/impacts.csv")) impacts(dir, cfg, p);
  return 0;
}

// Two-sphere impact: contact duration (from the surface gap, crossings
// interpolated), restitution, energy.
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

// Gravity pour: translational kinetic energy at the end (median of the last
// 0.2 s) relative to its peak,
// and the packing fraction of the bulk (2 diameters from the walls and the
// bottom, 4 below the free surface), by point sampling.
int pour(const std::string& dir) {
  const auto rows = read_series(dir + "/series/particles.csv");
  double peak = 0;
  for (const auto& r : rows) peak = nan_max(peak, r[5]);
  // The settled bed's kinetic energy: the median over the last 0.2 s (a few
  // grains keep spinning and now and then jostle a neighbour; one row would
  // catch or miss such an event by chance).
  std::vector<double> late;
  for (const auto& r : rows)
    if (r[0] >= rows.back()[0] - 0.2) late.push_back(r[5]);
  std::nth_element(late.begin(), late.begin() + late.size() / 2, late.end());
  const double settled = late[late.size() / 2];
  const auto snaps = snapshots(dir, "particles");
  const std::string f = dir + "/particles/" + output::snapshot_name(snaps.back().first);
  const auto x = output::read_dataset(f, "position");
  const auto rad = output::read_dataset(f, "radius");
  const std::size_t n = rad.size();
  const auto cfg = load(dir);
  double rmax = 0;
  std::vector<double> zs;
  for (std::size_t i = 0; i < n; ++i) {
    rmax = nan_max(rmax, rad[i]);
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
              n, top, settled / peak, rows.back().size() > 9 ? rows.back()[9] : 0.0,
              static_cast<double>(in) / total);
  return 0;
}

// Crushing with the automatic step: the smallest grain at the end against the
// largest at the start (how far crushing shrank them), the kinetic energy at
// the end against the start (a damped impact loses energy; an unstable step
// would gain it), and the steps taken against the sub-steps the run started
// with (above 1: the step was split as grains became lighter).
int crush(const std::string& dir) {
  const auto snaps = snapshots(dir, "particles");
  const auto r0 = output::read_dataset(dir + "/particles/" + output::snapshot_name(snaps.front().first), "radius");
  const auto r1 = output::read_dataset(dir + "/particles/" + output::snapshot_name(snaps.back().first), "radius");
  const auto rows = read_series(dir + "/series/particles.csv");
  const YAML::Node summary = YAML::LoadFile(dir + "/summary.json");
  const double steps = summary["components"]["particles"]["steps"].as<double>();
  const double windows = summary["windows"].as<double>();
  std::ifstream log(dir + "/logs/particles.log");
  double substeps = 0.0;
  for (std::string line; std::getline(log, line);)
    if (const auto at = line.find(" sub-steps of "); at != std::string::npos && substeps == 0.0)
      substeps = std::stod(line.substr(line.rfind(", ", at) + 2));
  if (substeps <= 0.0) throw std::runtime_error(dir + "/logs/particles.log: no sub-step line");
  std::printf("radius_ratio_min=%.6f\nenergy_ratio=%.6e\nstep_split=%.4f\n",
              *std::min_element(r1.begin(), r1.end()) / *std::max_element(r0.begin(), r0.end()),
              rows.back()[5] / rows.front()[5], steps / (windows * substeps));
  return 0;
}

}  // namespace coflow::check
