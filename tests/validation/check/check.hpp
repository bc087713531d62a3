// coflow-check: metrics of a finished run against analytic solutions and
// published data, printed as `name=value` lines for tests/validation/validate.sh.
// One file per physics (lbm.cpp, dem.cpp, psm.cpp, dpm.cpp) and the run-to-run
// comparison (compare.cpp); this header holds what they share: reading a run's
// resolved config.yaml, its series and its snapshots.
#pragma once

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "coflow/catalog.hpp"
#include "coflow/output.hpp"
#include "coflow/run_config.hpp"
#include "fluid/analytic/analytic_fluid.hpp"
#include "fluid/fluid_solver.hpp"

namespace coflow::check {

// The larger of two numbers, NaN if either is NaN: an error measure that
// meets a NaN stays NaN (std::max(x, NaN) gives x, which would let a run
// with NaN results pass), and a NaN printed fails every reference row.
inline double nan_max(double a, double b) {
  return (a != a || b != b) ? std::nan("") : std::max(a, b);
}
inline double nan_max(std::initializer_list<double> v) {
  double m = -std::numeric_limits<double>::infinity();
  for (const double x : v) m = nan_max(m, x);
  return m;
}

inline config::Config load(const std::string& dir) { return config::parse_config(dir + "/config.yaml", catalog()); }

inline fluid::FluidParams fluid_params(const config::Config& cfg) {
  fluid::FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);
  return p;
}

inline std::string last_snapshot(const std::string& dir, const std::string& component = "fluid") {
  std::ifstream in(dir + "/" + component + "/index.csv");
  std::string line, last;
  std::getline(in, line);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  if (last.empty()) throw std::runtime_error(dir + ": no " + component + " snapshot");
  return dir + "/" + component + "/" + output::snapshot_name(std::stol(last.substr(0, last.find(','))));
}

// A series file's rows (the header and the units line skipped); a file that
// cannot be read, or has no header, throws: a check must not see "no rows" as
// "nothing changed".
inline std::vector<std::vector<double>> read_series(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line))
    throw std::runtime_error(path + ": cannot read the series (missing or empty)");
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    if (line.starts_with("#")) continue;  // the units line
    std::vector<double> r;
    std::stringstream ss(line);
    for (std::string v; std::getline(ss, v, ',');) r.push_back(std::stod(v));
    rows.push_back(r);
  }
  return rows;
}

// A check's input with a NaN or an infinity in it (a run gone unstable) must
// fail, not pass through comparisons and max/min that drop NaN: throws.
inline void require_finite(const std::vector<double>& values, const std::string& what) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw std::runtime_error(what + ": value " + std::to_string(i) +
                               " is not finite (the run went unstable?)");
}

// The last row of a series, by column name.
class LastRow {
 public:
  explicit LastRow(const std::string& path) : path_(path), last_(read_series(path).back()) {
    std::ifstream in(path);
    std::string header;
    std::getline(in, header);
    std::stringstream hs(header);
    for (std::string c; std::getline(hs, c, ',');) names_.push_back(c);
  }
  double operator()(const std::string& name) const { return last_.at(column(name)); }
  bool has(const std::string& name) const { return std::find(names_.begin(), names_.end(), name) != names_.end(); }
  std::size_t column(const std::string& name) const {
    const auto it = std::find(names_.begin(), names_.end(), name);
    if (it == names_.end()) throw std::runtime_error(path_ + " has no column " + name);
    return static_cast<std::size_t>(it - names_.begin());
  }

 private:
  std::string path_;
  std::vector<double> last_;
  std::vector<std::string> names_;
};

// Kolmogorov-Smirnov distance between the sample x and the distribution cdf.
template <class Cdf>
double ks_distance(std::vector<double> x, Cdf cdf) {
  if (x.empty()) return std::nan("");  // no sample, no distance: fails any bound
  for (const double v : x)
    if (v != v) return std::nan("");
  std::sort(x.begin(), x.end());
  double d = 0.0;
  const double k = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double F = cdf(x[i]);
    d = nan_max({d, std::abs(F - i / k), std::abs(F - (i + 1) / k)});
  }
  return d;
}

inline std::vector<std::pair<long, double>> snapshots(const std::string& dir, const std::string& component) {
  std::ifstream in(dir + "/" + component + "/index.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::pair<long, double>> out;
  while (std::getline(in, line))
    if (!line.empty()) out.emplace_back(std::stol(line.substr(0, line.find(','))), std::stod(line.substr(line.find(',') + 1)));
  return out;
}

// lbm.cpp
int profile(const std::string& dir);
int dfg_cylinder(const std::string& dir);
int dfg_cylinder_unsteady(const std::string& dir);
int solid_channel(const std::string& dir);
int uniform_stream(const std::string& dir);
int inlet_profile(const std::string& dir);
int probes(const std::string& dir);
int hydrostatic(const std::string& dir);
int fluid_walls(const std::string& dir);
int walls_pressure_drop(const std::string& dir);
int channel(const std::string& dir);
int decay(const std::string& dir);
int ramp(const std::string& dir);
int mass(const std::string& dir);
// psm.cpp
int momentum(const std::string& dir);
int drag(const std::string& dir);
int buoyancy(const std::string& dir);
int settling(const std::string& dir);
int rotation(const std::string& dir);
// dem.cpp
int impact(const std::string& dir);
int walls(const std::string& dir);
int pour(const std::string& dir);
int crush(const std::string& dir);
// dpm.cpp
int dpm_settling(const std::string& dir);
int granular_gas(const std::string& dir);
int two_way(const std::string& dir);
int dispersion(const std::string& dir);
int grid_turbulence(const std::string& dir);
int grid_turbulence_fv(const std::string& dir);
int injection(const std::string& dir);
int jet(const std::string& dir);
int pair_into_mesh(const std::string& dir);
int inlet_stream(const std::string& dir);
int inlet_mass(const std::string& dir);
// fv/checks.cpp
int cavity(const std::string& dir);
int tg_error(const std::string& dir);
int stokes_layer(const std::string& dir);
int vortex(const std::string& dir);
int divergence(const std::string& dir);
int outflow_reflection(const std::string& a, const std::string& b);
// fv/turbulence_checks.cpp
int ke_decay(const std::string& dir);
int ke_grid(const std::string& dir);
int ke_grid_levels(const std::string& dir);
int ke_channel(const std::string& dir);
int ke_backward_step(const std::string& dir);
// two_phase/checks.cpp
int laplace(const std::string& dir);
int contact_angle(const std::string& dir);
int layered(const std::string& dir);
int colour_mass(const std::string& dir);
int permeability(const std::string& dir);
int washburn(const std::string& dir);
int injection_phase(const std::string& dir);
int grain_interface(const std::string& dir);
int bridge(const std::string& dir);
// immersed_boundary/checks.cpp
int ibm_steady(const std::string& dir);
int ibm_shedding(const std::string& dir);
int ibm_frames(const std::string& a, const std::string& b);
int ibm_extrapolated(const std::string& a, const std::string& b);
int ibm_oscillating(const std::string& dir);
int ibm_particles(const std::string& dir);
int ibm_balance(const std::string& dir);
int ibm_couette(const std::string& dir);
int ibm_couette_oscillating(const std::string& dir);
// compare.cpp
int compare(const std::string& a, const std::string& b);

}  // namespace coflow::check
