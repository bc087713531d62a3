// The particles' part of the pre-run report (coflow/report.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "coflow/output.hpp"
#include "particles/dem/stl.hpp"
#include "particles/particles_interface.hpp"
#include "particles/schema.hpp"
#include "particles/size_distribution.hpp"

namespace coflow::particles {

namespace {

// Partially saturated cells resolve a sphere with about 4 cells or more per
// diameter (the drag resolution study in docs/validation.md); the point model
// assumes particles smaller than a cell.
constexpr double kPsmCellsPerDiameter = 4.0;

// Rough costs for the wall-time estimate, one core of the project's 2-core
// VM (2026-12-07, session 78, compute time from the log): dem's gravity pour
// (2000 grains falling into a pack) 6.1e6 particle steps per second, dpm's
// granular gas (500 colliding particles) 3.7e6, and 1.7 us a step with 20
// grains; rounded the safe way.
constexpr double kDemParticleStepsPerRankPerSecond = 5e6;
constexpr double kDpmParticleStepsPerRankPerSecond = 3e6;
constexpr double kSecondsPerStep = 2e-6;
// Runs longer than this are warned of (as the fluid's).
constexpr double kLongRunHours = 12.0;

// How many particles the initial items other than files place (random fills
// by volume fraction at the species' mean diameter).
double initial_number(const ParticleParams& p) {
  double n = 0.0;
  for (const auto& it : p.initial) {
    const int s = p.species_index(it.species);
    if (it.kind == "single") n += 1;
    if (it.kind == "lattice") {
      double c = 1.0;
      for (int d = 0; d < 3; ++d) c *= std::max(1.0, std::floor((it.upper[d] - it.lower[d]) / it.spacing + 1e-9));
      n += c;
    }
    if (it.kind == "random" && it.count > 0) n += it.count;
    if (it.kind == "random" && it.count == 0 && s >= 0) {
      const double D = p.species[s].second.diameter.mean();
      double volume = 1.0;
      for (int d = 0; d < 3; ++d) volume *= it.upper[d] - it.lower[d];
      n += std::floor(it.volume_fraction * volume / sphere_volume(D));
    }
  }
  return n;
}

// How many particles the inlets bring in by run.end_time, at the species'
// mean diameter.
double injected_number(const ParticleParams& p, double end) {
  double n = 0.0;
  for (const auto& ip : p.injection) {
    const int s = p.species_index(ip.species);
    if (s < 0) continue;
    const double D = p.species[s].second.diameter.mean(), stop = ip.stop < 0.0 ? end : std::min(ip.stop, end);
    n += std::max(0.0, stop - ip.start) * ip.mass_flow / (p.species[s].second.density * sphere_volume(D));
  }
  return n;
}

void report_resolution(const ParticleParams& p, const config::Config& cfg, const std::string& method,
                       config::Report& r) {
  const double dx = cfg.domain.spacing()[0];
  for (const auto& [name, sp] : p.species) {
    const double D = sp.diameter.mean(), cells = D / dx;
    r.add("particles", "species " + name, fmt::format("D = {} m ({} cells per diameter), density {} kg/m^3",
                                                      config::number(D), config::number(cells),
                                                      config::number(sp.density)));
    if (method == "psm" && cells < kPsmCellsPerDiameter)
      r.warn("particles", fmt::format("species '{}' spans {} fluid cells (D/dx): partially saturated cells need "
                                      "about {} or more per diameter for the drag (docs/validation.md); refine "
                                      "domain.cells",
                                      name, config::number(cells), kPsmCellsPerDiameter));
    if (method == "point" && cells > 1.0)
      r.warn("particles", fmt::format("species '{}' is {} fluid cells across: the point-particle model assumes "
                                      "particles smaller than a cell; coarsen the grid or use dem with psm",
                                      name, config::number(cells)));
  }
}

// initial: file takes the radii of the file; say where they differ from what
// the species declare (the file's are used).
double report_initial_files(const ParticleParams& p, config::Report& r) {
  double count = 0.0;
  for (std::size_t n = 0; n < p.initial.size(); ++n) {
    const auto& it = p.initial[n];
    if (it.kind != "file") continue;
    std::vector<double> radius, species;
    try {
      radius = output::read_dataset(it.path.path, "radius");
      species = output::read_dataset(it.path.path, "species");
    } catch (const std::exception&) {
      continue;  // refused by validation (ParticleParams::check_file_inside)
    }
    count += static_cast<double>(radius.size());
    std::size_t off = 0;
    std::string example;
    for (std::size_t k = 0; k < radius.size() && k < species.size(); ++k) {
      const auto sk = static_cast<std::size_t>(species[k]);
      if (sk >= p.species.size()) continue;
      const auto& d = p.species[sk].second.diameter;
      const double D = 2.0 * radius[k];
      const bool fits = d.kind == config::Distribution::Kind::fixed     ? std::abs(D - d.a) <= 1e-9 * d.a
                        : d.kind == config::Distribution::Kind::uniform ? D >= d.a * (1 - 1e-9) && D <= d.b * (1 + 1e-9)
                                                                        : true;
      if (fits) continue;
      if (off++ == 0)
        example = fmt::format("diameter {} m where species '{}' says {} m", config::number(D), p.species[sk].first,
                              config::number(d.mean()));
    }
    r.add("particles", fmt::format("initial item {}", n), fmt::format("{} particles from {}", radius.size(), it.path.path));
    if (off > 0)
      r.warn("particles", fmt::format("initial item {}: {} of the {} particles of {} have other diameters than their "
                                      "species (e.g. {}); the file's radii are used",
                                      n, off, radius.size(), it.path.path, example));
  }
  return count;
}

// Steps of `step` to `end` (a step that divides it makes no extra one).
double step_count(double end, double step) {
  return std::max(1.0, std::ceil(end / step - 1e-9));
}

// The step and the steps it takes to run.end_time; auto: `e`, estimated from
// the species (automatic_step_estimate), the run logs the step it takes.
std::string step_text(const ParticleParams& p, const config::Config& cfg, const StepEstimate& e) {
  const double end = cfg.run.end_time;
  if (!p.time_step.is_auto)
    return fmt::format("{} s: {} steps to {} s", config::number(e.step),
                       config::number(step_count(end, e.step)), config::number(end));
  if (!(e.step > 0)) return "auto (chosen at the start, logged)";
  const std::string when = e.arriving ? "once grains arrive through the inlets" : "at the start";
  if (p.point_particles)
    return fmt::format(
        "auto: at most {} s {} (0.2 x the response time of the largest grains of species '{}', "
        "seed 003 eq. 4.15), so at least {} steps to {} s",
        config::number(e.step), when, e.species, config::number(step_count(end, e.step)),
        config::number(end));
  return fmt::format(
      "auto: at most {} s {} (the largest grains of species '{}'; the lightest grain sets it), at least {} "
      "steps to {} s",
      config::number(e.step), when, e.species, config::number(step_count(end, e.step)), config::number(end));
}

// A rough wall time of the particles: their steps to run.end_time (the
// automatic step from the species) times the mean number of particles (the
// initial ones and half of those the inlets bring), over the ranks, at a
// measured rate; 0 where the step is not known before the start.
double wall_estimate(const ParticleParams& p, const config::Config& cfg, double step, double particles) {
  if (!(step > 0)) return 0.0;
  const double rate =
      p.point_particles ? kDpmParticleStepsPerRankPerSecond : kDemParticleStepsPerRankPerSecond;
  const double steps = step_count(cfg.run.end_time, step);
  const int ranks = std::max(1, cfg.component("particles").ranks);
  return steps * (kSecondsPerStep + std::max(particles, 1.0) / (rate * ranks));
}

}  // namespace

void report(const config::Config& cfg, const std::string& variant, config::Report& r) {
  if (variant == "external") return;
  const ParticleParams p = read_particle_params(cfg, variant);
  // ibm with point particles couples them as method point does.
  const std::string method = !cfg.has("immersed")          ? ""
                             : config::point_coupling(cfg) ? "point"
                                                           : cfg.component("immersed").variant;
  const double placed = initial_number(p);
  const bool files =
      std::any_of(p.initial.begin(), p.initial.end(), [](const auto& it) { return it.kind == "file"; });
  r.add("particles", "initial particles",
        fmt::format("{}{}", config::number(placed), files ? " and those of the initial files" : ""));
  const double from_files = report_initial_files(p, r), injected = injected_number(p, cfg.run.end_time);
  if (!p.injection.empty())
    r.add("particles", "injection",
          fmt::format("{} inlet(s), about {} particles by {} s", p.injection.size(),
                      config::number(std::round(injected)), config::number(cfg.run.end_time)));
  // The step's upper bound for its line; the lower (each species' smallest
  // grains) for the wall time, which a job's time limit takes.
  const bool given = !p.time_step.is_auto;
  const StepEstimate e =
      given ? StepEstimate{p.time_step.value, "", false} : automatic_step_estimate(p, cfg, true);
  const double shortest = given ? p.time_step.value : automatic_step_estimate(p, cfg, false).step;
  r.add("particles", "time step", step_text(p, cfg, e));
  if (const double wall = wall_estimate(p, cfg, shortest, placed + from_files + 0.5 * injected); wall > 0) {
    r.estimate_wall(wall);
    r.add("particles", "wall time",
          fmt::format("about {} (a rough figure: {} particle steps per second per rank)",
                      config::duration(wall),
                      config::number(p.point_particles ? kDpmParticleStepsPerRankPerSecond
                                                       : kDemParticleStepsPerRankPerSecond)));
    if (wall > kLongRunHours * 3600.0)
      r.warn("particles",
             fmt::format("the run would take about {}: check particles.time_step (auto: the species' "
                         "sizes and densities{}), the number of particles and run.end_time",
                         config::duration(wall),
                         p.point_particles ? " and fluid.viscosity" : " and the contact stiffness"));
  }
  if (method == "point") {
    const std::string fluid = cfg.component("fluid").variant;
    r.add("particles", "coupling",
          p.coupling == "one-way" ? std::string("one-way (particles.coupling): the fluid does not feel the particles")
          : fluid == "analytic"   ? "one-way: fluid.solver analytic takes no momentum source"
                                  : std::string("two-way (the particles' momentum source acts on the fluid)"));
  }
  for (const auto& w : p.walls)
    if (!w.mesh.empty()) {
      try {
        r.add("particles", "mesh wall", describe_mesh(w, load_mesh(w)));
      } catch (const std::exception&) {
        // reported by validation
      }
    }
  if (cfg.has("fluid")) report_resolution(p, cfg, method, r);
  // (Point particles alone see the fluid section's fluid at rest, by design:
  // the settling and dispersion checks run that way.)
  if (cfg.has("fluid") && method.empty() && !p.point_particles)
    r.warn("particles",
           "the run has a fluid but no immersed section, so nothing couples them: the grains feel no "
           "fluid force and the fluid no grains; add immersed.method: psm");
}

}  // namespace coflow::particles
