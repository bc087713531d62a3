// The fluid's part of the pre-run report (coflow/report.hpp).
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "coflow/clock.hpp"
#include "coflow/decomposition.hpp"
#include "fluid/fv/params.hpp"
#include "fluid/lbm/params.hpp"
#include "fluid/lbm/units.hpp"
#include "fluid/params.hpp"
#include "fluid/schema.hpp"

namespace coflow::fluid {

namespace {

// A rough cost of one cell update of lbm per rank, for the wall-time estimate:
// bench-lbm gives about 100 million on a 256^3 block of the project's 2-core VM;
// small blocks, forces and psm cells are slower.
constexpr double kCellUpdatesPerRankPerSecond = 30e6;
// The colour-gradient kernel (two fluids or interior solids), one core of the
// same VM (2026-12-06, session 72): D3Q19 7.2e6 (two fluids, 64^3) and 8.3e6
// (one fluid around a sphere, 64^3); D2Q9 2.8e7 (two fluids, 256^2) and 3.8e7
// (the DFG cylinder, 440 x 82). The lower of each, rounded down.
constexpr double kColourCellUpdatesPerRankPerSecondD3Q19 = 7e6;
constexpr double kColourCellUpdatesPerRankPerSecondD2Q9 = 25e6;
// and a coupled window costs a few milliseconds of exchanges, waiting and the
// immersed side's work (the quickstart: 2280 windows in 10.4 s, of which the
// fluid's updates are 2.5 s).
constexpr double kSecondsPerCoupledWindow = 3.5e-3;
constexpr double kLongRunHours = 12.0;
// fv on one core of the same VM (2026-12-07, session 78; compute time from
// the log, steps from series/fluid.csv, memory the slope of the largest
// resident size between two grids): the Re 100 cavity 128^2 7.7e6 cell steps
// per second and 64^3 1.85e6 (32^3: 2.2e6); 2D 850 bytes per cell (128^2 to
// 512^2), 3D 1770 (32^3 to 64^3). fv-reference (unpreconditioned conjugate
// gradients: slower as the grid grows) 6.6e5 at 32^2 and 4.1e5 at 64^2. The
// log-law channel 256^2 with k-epsilon against without: 2.7x the time, 1.43x
// the memory (bench-fv's channel: 1.9x the time). Each rounded the safe way.
constexpr double kFvCellStepsPerRankPerSecond2D = 7e6;
constexpr double kFvCellStepsPerRankPerSecond3D = 1.8e6;
constexpr double kFvReferenceCellStepsPerSecond = 6e5;  // at kFvReferenceSide cells along the longest axis
constexpr double kFvReferenceSide = 32.0;               // and inversely as that side grows (64: 3e5)
constexpr double kFvKeCostFactor = 2.7;
constexpr double kFvBytesPerCell2D = 850.0;
constexpr double kFvBytesPerCell3D = 1800.0;
constexpr double kFvKeMemoryFactor = 1.45;

// sum_d 1 / dx_d over the grid's axes (an axis one cell across is not one).
double inverse_spacing_sum(const config::DomainParams& d) {
  double s = 0.0;
  const auto h = d.spacing();
  for (int a = 0; a < 3; ++a)
    if (d.cells[a] > 1) s += 1.0 / h[a];
  return s;
}

FluidParams read_fluid(const config::Config& cfg) {
  FluidParams p;
  config::Reader r(cfg.resolved["fluid"], cfg.file, "fluid");
  p.visit(r, cfg);
  return p;
}

// The largest |factor| of a velocity face's profile over the centres of the
// cells on the face (1 for a uniform face); a formula in t at up to 65 times
// in [0, end] (fewer on a large face: about 2e5 evaluations at most), spread
// by the golden ratio's fractional parts so that no periodic formula is
// sampled only at its zeros. NaN if the formula gives one.
static double largest_factor(int face, const BoundaryParams& b, const config::Config& cfg) {
  if (b.profile == "uniform") return 1.0;
  const int axis = face / 2, ta = axis == 0 ? 1 : 0, tb = axis == 2 ? 1 : 2;
  const auto& n = cfg.domain.cells;
  const bool in_time = b.profile == "expression" && b.formula.uses_time();
  const long times = in_time ? std::clamp(200000L / (n[ta] * n[tb]), 2L, 65L) : 1;
  double largest = 0.0, s[3] = {0.5, 0.5, 0.5};
  s[axis] = face % 2 == 0 ? 0.0 : 1.0;
  for (long k = 0; k < times; ++k) {
    const double t = cfg.run.end_time * std::fmod(0.6180339887498949 * static_cast<double>(k), 1.0);
    for (long c = 0; c < n[tb]; ++c)
      for (long a = 0; a < n[ta]; ++a) {
        s[ta] = (a + 0.5) / n[ta], s[tb] = (c + 0.5) / n[tb];
        const double v = std::abs(b.profile_factor(face, s, cfg, t));
        largest = v > largest || v != v ? v : largest;
      }
  }
  return largest;
}

// The largest speed the configuration gives: initial velocity (or Taylor-Green
// amplitude) and velocity faces (times their profiles' largest factor).
// 0 when a force or a pressure drop drives the flow.
double velocity_scale(const FluidParams& p, const config::Config& cfg) {
  double u = std::sqrt(p.initial_velocity[0] * p.initial_velocity[0] + p.initial_velocity[1] * p.initial_velocity[1] +
                       p.initial_velocity[2] * p.initial_velocity[2]);
  if (p.initial_field == "taylor-green") u = std::max(u, std::abs(p.initial_amplitude));
  for (int f = 0; f < 6; ++f) {
    const BoundaryParams b = p.boundary(f, cfg);
    if (b.type != "velocity") continue;
    double s = 0.0;
    for (double x : b.value.values) s += x * x;
    u = std::max(u, std::sqrt(s) * largest_factor(f, b, cfg));
  }
  return u;
}

void report_mach(config::Report& r, double u, const lbm::Units& units, double tau, double dx) {
  if (u <= 0.0) {
    r.add("fluid", "velocity scale",
          "no initial or boundary velocity: Mach is checked as the run goes (a warning above 0.1, a stop above 0.3)");
    return;
  }
  const double lattice_u = u / units.velocity(), mach = lattice_u * std::sqrt(3.0);
  r.add("fluid", "velocity scale", fmt::format("U = {} m/s (largest initial or boundary velocity)", config::number(u)));
  r.add("fluid", "Mach", fmt::format("{} (lattice speed U dt/dx = {})", config::number(mach), config::number(lattice_u)));
  if (mach <= 0.1) return;
  // With dx and nu fixed, Mach is proportional to tau - 1/2 and to dx.
  const double tau01 = 0.5 + (tau - 0.5) * 0.1 / mach;
  r.warn("fluid", fmt::format("Mach {} > 0.1 at U = {} m/s: compressibility errors grow as Ma^2; {}",
                              config::number(mach), config::number(u),
                              tau01 >= 0.51 ? fmt::format("fluid.lbm.tau {} gives Mach 0.1 at this dx", config::number(tau01))
                                            : fmt::format("cells of {} m give Mach 0.1 at this tau (tau below 0.51 "
                                                          "is unstable)",
                                                          config::number(dx * 0.1 / mach))));
}

// The pressure faces' lattice densities 1 + p / (rho c_s^2): the standard
// formulation's compressibility error grows with their differences (He-Luo's
// incompressible one takes the density for a pressure).
void report_pressure_faces(config::Report& r, const FluidParams& fp, const config::Config& cfg,
                           const lbm::Units& units, bool standard) {
  double lo = 1e300, hi = -1e300;
  for (int f = 0; f < 6; ++f) {
    const BoundaryParams b = fp.boundary(f, cfg);
    if (b.type != "pressure" || b.value.values.empty()) continue;
    const double rho = units.lattice_density(b.value.values[0]);
    lo = std::min(lo, rho), hi = std::max(hi, rho);
  }
  if (lo > hi) return;  // no pressure face
  r.add("fluid", "pressure faces",
        fmt::format("lattice densities {} to {}", config::number(lo), config::number(hi)));
  const double off = std::max(std::abs(lo - 1.0), std::abs(hi - 1.0));
  if (off > 0.1 && standard)
    r.warn("fluid",
           fmt::format("a pressure face's lattice density is {} from 1 (more than 0.1): the "
                       "compressibility error grows with it; give the pressures relative to the mean "
                       "one, lower the pressure drop, or take a shorter step (a smaller fluid.lbm.tau)",
                       config::number(off)));
}

// fluid.solids and how their surfaces are taken (fluid.lbm.bounce_back).
void report_solids(config::Report& r, const config::Config& cfg, const FluidParams& fp,
                   const lbm::LbmParams& lp) {
  const bool interpolated = lp.bounce_back != "halfway";  // interpolated or central
  long voxels = 0;
  for (const auto& s : fp.solids) voxels += s.kind == "voxels" ? 1 : 0;
  if (fp.solids.empty()) {
    if (interpolated)
      r.warn("fluid", fmt::format("fluid.lbm.bounce_back: {} has no effect without fluid.solids (the box's "
                                  "walls are half-way bounce-back)",
                                  lp.bounce_back));
    return;
  }
  const bool shapes = voxels < static_cast<long>(fp.solids.size());  // spheres, boxes or meshes
  r.add("fluid", "solids",
        fmt::format("{} of fluid.solids ({} of them voxel images), {} bounce-back{}", fp.solids.size(),
                    voxels, lp.bounce_back,
                    shapes && lp.bounce_back == "interpolated" && lp.collision == "trt"
                        ? " (with TRT its wall moves with tau; central's does not: docs/validation.md)"
                        : ""));
  // The solids are the fluid's: the particles (dem, dpm) collide with their
  // own walls only, and psm drops a grain's cover where a solid is.
  bool moving = false;  // a species whose grains move (fixed ones stay where they were put)
  if (const YAML::Node species = config::resolved_node(cfg, "particles.species"); species.IsMap())
    for (const auto& s : species) moving = moving || !(s.second["fixed"] && s.second["fixed"].as<bool>());
  if (cfg.has("particles") && moving && !config::resolved_node(cfg, "particles.walls").IsSequence())
    r.warn("fluid",
           "fluid.solids are the fluid's alone: particles pass through them (they collide with the "
           "faces and meshes of particles.walls only); give particles.walls a mesh of each solid the "
           "grains can reach");
  if (interpolated && !shapes)
    r.warn("fluid", fmt::format("fluid.lbm.bounce_back: {} has no effect on voxel images (their surface is "
                                "their voxels' faces, half-way between the centres); it needs spheres, boxes "
                                "or meshes",
                                lp.bounce_back));
}

// One fluid rank would need more memory than this whole machine has: say so.
// (All ranks together are not compared: a cluster job spreads them over
// nodes, and the launcher cannot tell how many share one.)
void warn_memory(config::Report& r, double bytes_per_rank) {
  const double host = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  if (!(host > 0.0) || !(bytes_per_rank > host)) return;
  r.warn("fluid",
         fmt::format("each fluid rank needs about {} GiB, more than this machine's {} GiB in all: use "
                     "fewer cells or more ranks (fluid.ranks), on nodes that hold it",
                     config::number(bytes_per_rank / (1 << 30)), config::number(host / (1 << 30))));
}

// The step and the count of steps to the end (one at least: a step longer
// than the run, which the report warns of, still makes one), returned.
double report_lbm_step(config::Report& r, double dt, double tau, double end) {
  const double steps = std::max(1.0, std::ceil(end / dt - 1e-9));
  r.add("fluid", "time step",
        fmt::format("dt = {} s: {} step{} to {} s", config::number(dt), config::number(steps),
                    steps == 1 ? "" : "s", config::number(end)));
  if (dt > end * (1 + 1e-6))
    r.warn("fluid",
           fmt::format("the lattice step dt = {} s (fluid.lbm.tau {}) is longer than run.end_time {} s: the "
                       "run makes one step and ends at t = {} s; lower tau towards 0.5, use finer cells, "
                       "or run longer",
                       config::number(dt), config::number(tau), config::number(end), config::number(dt)));
  return steps;
}

// The grid line; returns the most cells a rank holds.
long report_grid(const config::Config& cfg, config::Report& r) {
  const auto& d = cfg.domain;
  const long cells = static_cast<long>(d.cells[0]) * d.cells[1] * d.cells[2];
  const auto& info = cfg.component("fluid");
  std::array<int, 3> dims{0, 0, 0};
  if (!info.decomposition.is_auto) dims = info.decomposition.value;
  const coupler::Decomposition dec({d.cells[0], d.cells[1], d.cells[2]}, info.ranks, dims, d.periodic);
  long block = 0;
  for (int k = 0; k < info.ranks; ++k) block = std::max(block, dec.block(k).volume());
  r.add("fluid", "grid",
        fmt::format("{} x {} x {} cells of {} m ({} cells; at most {} per rank)", d.cells[0], d.cells[1],
                    d.cells[2], config::number(d.spacing()[0]), cells, block));
  return block;
}

void report_reynolds(const config::Config& cfg, double u, double nu, config::Report& r) {
  const auto& d = cfg.domain;
  double L = 1e300;
  for (int a = 0; a < (d.two_dimensional() ? 2 : 3); ++a) L = std::min(L, d.upper[a] - d.lower[a]);
  r.add("fluid", "Reynolds",
        fmt::format("Re = U L / nu = {} (L = {} m, the smallest side of the box)", config::number(u * L / nu),
                    config::number(L)));
}

// The wall-time line (`rate`: what the figure assumes) and the warning of a
// long run, which names the keys to check.
void report_wall(config::Report& r, double steps, long block, double rate, const std::string& assumed,
                 const std::string& keys) {
  const double seconds = steps * block / rate;
  r.estimate_wall(seconds);
  r.add("fluid", "wall time",
        fmt::format("about {} (a rough figure: {})", config::duration(seconds), assumed));
  if (seconds > kLongRunHours * 3600.0)
    r.warn("fluid",
           fmt::format("the run would take about {} ({} steps of {} cells per rank): check {}, the grid "
                       "and run.end_time",
                       config::duration(seconds), config::number(steps), block, keys));
}

void report_lbm(const config::Config& cfg, config::Report& r) {
  const FluidParams fp = read_fluid(cfg);
  const auto lp = config::read_section<lbm::LbmParams>(cfg, "fluid.lbm", "fluid.lbm");
  const auto& d = cfg.domain;
  const double dx = d.spacing()[0];
  // The step the coupling window asks for (coupler::output_window): tau adjusted.
  const double natural = lbm::Units::from(dx, fp.viscosity, fp.density, lp.tau).dt;
  const double window = coupler::output_window(natural, cfg);
  const bool adjusted = cfg.coupling.window.is_auto && window < natural * (1 - 1e-12);
  const double tau = adjusted ? lbm::tau_for_step(lp.tau, window, dx, fp.viscosity) : lp.tau;
  const lbm::Units units = lbm::Units::from(dx, fp.viscosity, fp.density, tau);
  const long block = report_grid(cfg, r);
  r.add("fluid", "lattice", fmt::format("{} {}, tau {}, {}{}", lp.lattice, lp.collision, config::number(tau),
                                        lp.formulation,
                                        adjusted ? fmt::format(" (fluid.lbm.tau {} shortened the step by {}% so that "
                                                               "snapshots fall at multiples of run.output.every)",
                                                               config::number(lp.tau),
                                                               config::number(100.0 * (1.0 - window / natural)))
                                                 : ""));
  const double steps = report_lbm_step(r, units.dt, lp.tau, cfg.run.end_time);
  const double u = velocity_scale(fp, cfg);
  report_mach(r, u, units, tau, dx);
  report_pressure_faces(r, fp, cfg, units, lp.formulation == "standard");
  report_solids(r, cfg, fp, lp);
  if (fp.two_phase.on) {
    const double nu_b = fp.two_phase.viscosity_blue > 0.0 ? fp.two_phase.viscosity_blue : fp.viscosity;
    const double tau_b = 0.5 + 3.0 * nu_b * units.dt / (dx * dx);
    const double gamma = fp.two_phase.surface_tension * units.dt * units.dt / (units.rho * dx * dx * dx);
    r.add("fluid", "two fluids",
          fmt::format("tau red {}, blue {}; surface tension {} in lattice units", config::number(tau),
                      config::number(tau_b), config::number(gamma)));
    if (tau_b < 0.51)
      r.warn("fluid", fmt::format("the blue fluid's tau is {} (fluid.two_phase.viscosity_blue {} m^2/s): below "
                                  "0.51 the collision is close to unstable; raise fluid.lbm.tau or the viscosity",
                                  config::number(tau_b), config::number(nu_b)));
  }
  if (u > 0.0) report_reynolds(cfg, u, fp.viscosity, r);
  const int Q = lp.lattice == "D2Q9" ? 9 : 19;
  // Two fluids, or interior solids: red and blue populations (two copies
  // each), the colour field and the solid map; the colour kernel's rate.
  const bool colours = fp.two_phase.on || !fp.solids.empty();
  const double colour_rate =
      Q == 9 ? kColourCellUpdatesPerRankPerSecondD2Q9 : kColourCellUpdatesPerRankPerSecondD3Q19;
  const double copies = colours ? 4.0 : 2.0, rate = colours ? colour_rate : kCellUpdatesPerRankPerSecond;
  const double bytes = (copies * Q + (colours ? 1.2 : 0.0)) * 8.0 * block * 1.1;
  r.add("fluid", "memory",
        fmt::format("about {} MiB per rank ({} copies of {} populations per cell{})",
                    config::number(bytes / (1 << 20)), colours ? "four" : "two", Q,
                    colours ? ": red and blue" : ""));
  warn_memory(r, bytes);
  const double windows = cfg.components.size() > 1 ? std::ceil(cfg.run.end_time / window - 1e-9) : 0.0;
  // The coupled windows' cost as that of more cell updates.
  const double effective = steps * block / (steps * block / rate + windows * kSecondsPerCoupledWindow);
  report_wall(
      r, steps, block, effective,
      fmt::format("{} cell updates per second per rank{}", config::number(rate),
                  windows > 0 ? fmt::format(", {} s per coupled window", kSecondsPerCoupledWindow) : ""),
      "fluid.viscosity (water: 1e-6 m^2/s), fluid.lbm.tau");
}

// The fv step at the speed u (u > 0), with the line that says it; returns
// the steps to the end.
double report_fv_step(const config::Config& cfg, const fv::FvParams& fv, double u, config::Report& r) {
  const double end = cfg.run.end_time;
  double dt = fv.cfl / (u * inverse_spacing_sum(cfg.domain));  // eq. 4.1 with U along every axis
  if (fv.max_step > 0) dt = std::min(dt, fv.max_step);
  const double steps = std::max(1.0, std::ceil(end / dt - 1e-9));
  r.add(
      "fluid", "time step",
      fmt::format("about {} s at U (C / sum_d(U / dx_d), seed 003 eq. 4.1{}; it follows the flow): about {} "
                  "steps to {} s",
                  config::number(dt), fv.max_step > 0 ? ", at most fluid.fv.max_step" : "",
                  config::number(steps), config::number(end)));
  return steps;
}

// fv's rate of cell steps per rank: measured (above); fv-reference's
// unpreconditioned solves slow as the grid's longest side grows, and its 3D
// rate is taken as fv's ratio of 3D to 2D (measured in 2D only).
double fv_cell_rate(const config::DomainParams& d, const std::string& variant, bool ke) {
  const bool flat = d.two_dimensional();
  const double side = std::max({d.cells[0], d.cells[1], d.cells[2]});
  const double fv = flat ? kFvCellStepsPerRankPerSecond2D : kFvCellStepsPerRankPerSecond3D;
  const double rate = variant == "fv"
                          ? fv
                          : kFvReferenceCellStepsPerSecond * kFvReferenceSide /
                                std::max(side, kFvReferenceSide) * fv / kFvCellStepsPerRankPerSecond2D;
  return rate / (ke ? kFvKeCostFactor : 1.0);
}

// fv and fv-reference: the grid, the speed and the step the CFL condition
// gives at it (seed 003 eq. 4.1; the run's step follows the flow), memory and
// a rough wall time. The adaptive grid's cells change as it runs: its grid
// and step only.
void report_fv(const config::Config& cfg, const std::string& variant, config::Report& r) {
  const FluidParams fp = read_fluid(cfg);
  const auto fv = config::read_section<fv::FvParams>(cfg, "fluid.fv", "fluid.fv");
  const long block = report_grid(cfg, r);
  const double u = velocity_scale(fp, cfg);
  double steps = 0.0;
  if (u > 0.0) {
    r.add("fluid", "velocity scale",
          fmt::format("U = {} m/s (largest initial or boundary velocity)", config::number(u)));
    report_reynolds(cfg, u, fp.viscosity, r);
    steps = report_fv_step(cfg, fv, u, r);
  } else {
    r.add("fluid", "time step",
          fmt::format(
              "follows the flow (seed 003 eq. 4.1, C = {}): no initial or boundary velocity to estimate "
              "it from, so no wall-time estimate",
              config::number(fv.cfl)));
  }
  if (fv.refinement.on) {
    r.add("fluid", "refinement",
          fmt::format("{} levels, the finest the grid above: the cells change as the run refines and "
                      "coarsens, so no memory or wall-time estimate",
                      fv.refinement.levels));
    return;
  }
  const bool ke = fp.turbulence.on;
  const double per_cell =
      (cfg.domain.two_dimensional() ? kFvBytesPerCell2D : kFvBytesPerCell3D) * (ke ? kFvKeMemoryFactor : 1.0);
  r.add("fluid", "memory",
        fmt::format("about {} MiB per rank (about {} bytes per cell{})",
                    config::number(per_cell * block / (1 << 20)), config::number(per_cell),
                    ke ? " with k-epsilon" : ""));
  warn_memory(r, per_cell * block);
  if (steps <= 0.0) return;
  const double cell_rate = fv_cell_rate(cfg.domain, variant, ke);
  report_wall(r, steps, block, cell_rate,
              fmt::format("{} cell steps per second per rank{}", config::number(cell_rate),
                          ke ? " (k-epsilon included)" : ""),
              "fluid.viscosity, fluid.fv.cfl");
}

}  // namespace

void report(const config::Config& cfg, const std::string& variant, config::Report& r) {
  if (variant == "lbm" || variant == "lbm-reference") {
    report_lbm(cfg, r);
    return;
  }
  if (variant == "fv" || variant == "fv-reference") {
    report_fv(cfg, variant, r);
    return;
  }
  if (variant == "analytic")
    r.add("fluid", "flow",
          "prescribed (" + config::resolved_text(cfg, {"fluid", "analytic", "field"}) +
              "), exact at any time; no time step");
}

double largest_profile_factor(int face, const BoundaryParams& b, const config::Config& cfg) {
  return largest_factor(face, b, cfg);
}

}  // namespace coflow::fluid
