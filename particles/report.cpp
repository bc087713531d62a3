// The particles' part of the pre-run report (coflow/report.hpp).
#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "coflow/output.hpp"
#include "particles/dem/stl.hpp"
#include "particles/particles_interface.hpp"
#include "particles/schema.hpp"

namespace coflow::particles {

namespace {

// Partially saturated cells resolve a sphere with about 4 cells or more per
// diameter (the drag resolution study in docs/validation.md); the point model
// assumes particles smaller than a cell.
constexpr double kPsmCellsPerDiameter = 4.0;

ParticleParams read_particles(const config::Config& cfg, const std::string& variant) {
  ParticleParams p;
  p.point_particles = variant == "dpm" || variant == "dpm-reference";
  config::Reader r(cfg.resolved["particles"], cfg.file, "particles");
  p.visit(r, cfg);
  return p;
}

// How many particles the initial items place (random fills by volume fraction
// at the species' mean diameter; files are not opened).
std::string initial_count(const ParticleParams& p) {
  double n = 0.0;
  bool files = false;
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
      n += std::floor(it.volume_fraction * volume / (std::numbers::pi * D * D * D / 6.0));
    }
    files = files || it.kind == "file";
  }
  return fmt::format("{}{}", config::number(n), files ? " and those of the initial files" : "");
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
void report_initial_files(const ParticleParams& p, config::Report& r) {
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
}

}  // namespace

void report(const config::Config& cfg, const std::string& variant, config::Report& r) {
  if (variant == "external") return;
  const ParticleParams p = read_particles(cfg, variant);
  // ibm with point particles couples them as method point does.
  const std::string method = !cfg.has("immersed")          ? ""
                             : config::point_coupling(cfg) ? "point"
                                                           : cfg.component("immersed").variant;
  r.add("particles", "initial particles", initial_count(p));
  report_initial_files(p, r);
  if (!p.injection.empty()) r.add("particles", "injection", fmt::format("{} inlet(s)", p.injection.size()));
  r.add("particles", "time step",
        p.time_step.is_auto ? std::string("auto (chosen at start, logged)") : config::number(p.time_step.value) + " s");
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
