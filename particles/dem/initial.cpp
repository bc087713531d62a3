#include "particles/dem/initial.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include <fmt/format.h>

#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "particles/size_distribution.hpp"

namespace coflow::particles::dem {

namespace {

double sample_diameter(const config::Distribution& d, std::mt19937_64& rng) {
  switch (d.kind) {
    case config::Distribution::Kind::fixed: return d.a;
    case config::Distribution::Kind::uniform: return std::uniform_real_distribution<double>(d.a, d.b)(rng);
    case config::Distribution::Kind::lognormal: {
      std::normal_distribution<double> normal(0.0, 1.0);
      return truncated_lognormal(d.a, d.b, [&](int) { return normal(rng); });
    }
  }
  return d.a;
}

void add(ParticleArrays& a, int species, double density, double diameter, const V3& x, const V3& v, const V3& w) {
  a.id.push_back(static_cast<std::int64_t>(a.id.size()));
  a.species.push_back(species);
  for (int d = 0; d < 3; ++d) {
    a.x.push_back(x[d]);
    a.v.push_back(v[d]);
    a.w.push_back(w[d]);
    a.force.push_back(0.0);
  }
  const double r = 0.5 * diameter;
  const double m = density * std::numbers::pi * diameter * diameter * diameter / 6.0;
  a.radius.push_back(r);
  a.mass.push_back(m);
  a.inertia.push_back(0.4 * m * r * r);
}

// A simple cubic lattice of species s filling the item's region.
void add_lattice(ParticleArrays& a, const ParticleParams& p, const InitialItem& it, int s, std::mt19937_64& rng) {
  const auto& sp = p.species[s].second;
  long n[3];
  for (int d = 0; d < 3; ++d) n[d] = std::max(1L, static_cast<long>(std::floor((it.upper[d] - it.lower[d]) / it.spacing + 1e-9)));
  for (long k = 0; k < n[2]; ++k)
    for (long j = 0; j < n[1]; ++j)
      for (long i = 0; i < n[0]; ++i) {
        const V3 x(it.lower[0] + (i + 0.5) * it.spacing, it.lower[1] + (j + 0.5) * it.spacing,
                   it.lower[2] + (k + 0.5) * it.spacing);
        add(a, s, sp.density, sample_diameter(sp.diameter, rng), x, V3(it.velocity.data()), V3::Zero());
      }
}

// Random sequential addition: draw a size and a position, keep it if it
// overlaps nothing placed before, by this item or an earlier one (checked on
// a cell grid).
void add_random(ParticleArrays& a, const ParticleParams& p, const InitialItem& it, int s, std::mt19937_64& rng) {
  const auto& sp = p.species[s].second;
  const V3 lo(it.lower.data()), hi(it.upper.data());
  const double volume = (hi - lo).prod();
  const double target_volume = it.volume_fraction * volume;
  double placed_volume = 0.0;
  long placed = 0;
  // The largest diameter the species draws (a log-normal's cut-off, mean + 6
  // standard deviations: the draws are not clamped below it).
  const double dmax = largest_diameter(sp.diameter);
  // Overlap search grid: cells of at least the largest diameter here (this
  // item's or an earlier particle's), at most 128 per axis; the particles of
  // earlier items within reach of the region go in first (those outside it
  // into its edge cells, no farther in cells from a new one than their own).
  double cell = dmax;
  for (double r : a.radius) cell = std::max(cell, 2.0 * r);
  std::vector<std::vector<long>> grid;
  std::array<long, 3> nc{};
  for (int d = 0; d < 3; ++d) nc[d] = std::clamp(static_cast<long>((hi[d] - lo[d]) / cell), 1L, 128L);
  grid.resize(nc[0] * nc[1] * nc[2]);
  auto cell_of = [&](const V3& x) {
    std::array<long, 3> c{};
    for (int d = 0; d < 3; ++d) c[d] = std::clamp(static_cast<long>((x[d] - lo[d]) / (hi[d] - lo[d]) * nc[d]), 0L, nc[d] - 1);
    return c;
  };
  for (std::size_t q = 0; q < a.size(); ++q) {
    const V3 y(&a.x[3 * q]);
    if (((y.array() >= lo.array() - cell) && (y.array() <= hi.array() + cell)).all()) {
      const auto c = cell_of(y);
      grid[(c[2] * nc[1] + c[1]) * nc[0] + c[0]].push_back(static_cast<long>(q));
    }
  }
  std::normal_distribution<double> vel(0.0, it.velocity_std);
  long attempts = 0;
  while ((it.count > 0 && placed < it.count) || (it.count == 0 && placed_volume < target_volume)) {
    if (++attempts > 1000 * (placed + 100))
      throw std::runtime_error(fmt::format(
          "particles.initial: random fill of species '{}' placed only {} particles (solid fraction {:.3f}) before "
          "running out of room; use fewer particles, a larger region, or a lattice",
          it.species, placed, placed_volume / volume));
    const double diam = sample_diameter(sp.diameter, rng);
    if (((hi - lo).array() < diam).any())
      continue;  // wider than the region: drawn again (counted as an attempt)
    V3 x;
    for (int d = 0; d < 3; ++d)
      x[d] = std::uniform_real_distribution<double>(lo[d] + 0.5 * diam, hi[d] - 0.5 * diam)(rng);
    const auto c = cell_of(x);
    bool free = true;
    for (long dz = -1; dz <= 1 && free; ++dz)
      for (long dy = -1; dy <= 1 && free; ++dy)
        for (long dx = -1; dx <= 1 && free; ++dx) {
          const long cx = c[0] + dx, cy = c[1] + dy, cz = c[2] + dz;
          if (cx < 0 || cy < 0 || cz < 0 || cx >= nc[0] || cy >= nc[1] || cz >= nc[2]) continue;
          for (long q : grid[(cz * nc[1] + cy) * nc[0] + cx]) {
            const V3 y(&a.x[3 * q]);
            if ((y - x).norm() < a.radius[q] + 0.5 * diam) {
              free = false;
              break;
            }
          }
        }
    if (!free) continue;
    const V3 mean(it.velocity[0], it.velocity[1], it.velocity[2]);
    const V3 v = it.velocity_std > 0 ? V3(vel(rng), vel(rng), vel(rng)) : V3::Zero();
    add(a, s, sp.density, diam, x, mean + v, V3::Zero());
    grid[(c[2] * nc[1] + c[1]) * nc[0] + c[0]].push_back(static_cast<long>(a.size() - 1));
    placed_volume += std::numbers::pi * diam * diam * diam / 6.0;
    ++placed;
  }
}

// Particles from an HDF5 snapshot written by coflow.
void add_from_file(ParticleArrays& a, const ParticleParams& p, const InitialItem& it) {
  std::vector<std::size_t> dims;
  const std::string& file = it.path.path;
  const auto x = output::read_dataset(file, "position", &dims);
  const auto v = output::read_dataset(file, "velocity");
  const auto w = output::read_dataset(file, "angular_velocity");
  const auto r = output::read_dataset(file, "radius");
  const auto sp = output::read_dataset(file, "species");
  if (const std::string wrong = snapshot_shape_error(r.size(), x.size(), v.size(), w.size(), sp.size());
      !wrong.empty())
    throw std::runtime_error(fmt::format("{}: {}", file, wrong));
  for (std::size_t n = 0; n < r.size(); ++n) {
    if (!(sp[n] >= 0 && sp[n] < static_cast<double>(p.species.size())))
      throw std::runtime_error(fmt::format("{}: particle {} has species {}, but only {} are defined", file, n,
                                           sp[n], p.species.size()));
    const int s2 = static_cast<int>(sp[n]);
    // The ghost layers (of the particles and of psm's cover) are as wide as
    // the species' largest diameter: a larger grain would be cut on N ranks.
    const double largest = largest_diameter(p.species[s2].second.diameter);
    if (!(r[n] > 0 && 2.0 * r[n] <= largest * (1.0 + 1e-12)))
      throw std::runtime_error(
          fmt::format("{}: particle {} has a diameter of {:.6g} m, but its species {} is at most "
                      "{:.6g} m: give the species that diameter (or the file smaller grains)",
                      file, n, 2.0 * r[n], p.species[s2].first, largest));
    add(a, s2, p.species[s2].second.density, 2.0 * r[n], V3(&x[3 * n]), V3(&v[3 * n]), V3(&w[3 * n]));
  }
}

}  // namespace

ParticleArrays make_initial(const ParticleParams& p, const config::Config& cfg) {
  ParticleArrays a;
  std::mt19937_64 rng(cfg.run.seed);
  for (const auto& it : p.initial) {
    const int s = p.species_index(it.species);
    if (it.kind == "single") {
      const auto& sp = p.species[s].second;
      add(a, s, sp.density, sample_diameter(sp.diameter, rng), V3(it.position.data()), V3(it.velocity.data()),
          V3(it.angular_velocity.data()));
    } else if (it.kind == "lattice") {
      add_lattice(a, p, it, s, rng);
    } else if (it.kind == "random") {
      add_random(a, p, it, s, rng);
    } else if (it.kind == "file") {
      add_from_file(a, p, it);
    }
  }
  // On a periodic axis a centre on the upper face is the lower face's: both
  // variants start from [lower, upper) (dem wraps no fixed grain later,
  // dem-reference every grain).
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int d = 0; d < 3; ++d)
      if (cfg.domain.periodic[d] && a.x[3 * i + d] >= cfg.domain.upper[d])
        a.x[3 * i + d] -= cfg.domain.upper[d] - cfg.domain.lower[d];
  return a;
}

DemSetup make_setup(const ParticleParams& p, const config::Config& cfg, const ParticleArrays& parts) {
  DemSetup s;
  const auto& c = p.contact;
  s.law = {c.normal_stiffness, c.shear_stiffness, c.friction, 0.0, 0.0, 0.0};
  if (c.bonded) {
    s.law.sigma_c = c.bond.compressive_strength;
    s.law.sigma_t = c.bond.tensile_strength;
    s.law.tau_c = c.bond.shear_strength;
    s.crush = c.bond.crush_fraction;
    s.bond_gap = c.bond.gap;
    s.bond_file = c.bond.pairs.path;
  }
  s.alpha = c.local_damping;
  for (const auto& [name, sp] : p.species) s.fixed.push_back(sp.fixed ? 1 : 0);
  for (int d = 0; d < 3; ++d) {
    s.gravity[d] = cfg.gravity[d];
    s.lower[d] = cfg.domain.lower[d];
    s.upper[d] = cfg.domain.upper[d];
    s.periodic[d] = cfg.domain.periodic[d];
  }
  const char* names[] = {"x-", "x+", "y-", "y+", "z-", "z+"};
  for (int f = 0; f < 6; ++f) {
    s.wall_friction[f] = c.friction;
    if (cfg.domain.periodic[f / 2]) {
      s.faces[f] = Face::periodic;
      continue;
    }
    s.faces[f] = p.boundaries[f] == "outlet" ? Face::outlet : Face::wall;
    for (const auto& w : p.walls) {
      if (w.face == names[f]) {
        s.faces[f] = Face::wall;
        if (w.friction >= 0) s.wall_friction[f] = w.friction;
      }
    }
  }
  for (const auto& w : p.walls) {
    if (w.mesh.empty()) continue;
    dem::TriangleMesh m = load_mesh(w);
    log::info("mesh wall {}", describe_mesh(w, m));
    s.meshes.emplace_back(std::move(m), w.friction >= 0 ? w.friction : c.friction);
  }
  // Time step, seed 000 eqs 2.19-2.20, and no more than half a dense pack's
  // critical step (contact.hpp, automatic_step).
  const double k = std::max(c.normal_stiffness, c.shear_stiffness);
  double crit = 1e300, lightest = 1e300;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    crit = std::min(crit, critical_step(parts.mass[i], k));
    lightest = std::min(lightest, parts.mass[i]);
    s.max_radius = std::max(s.max_radius, parts.radius[i]);
  }
  s.auto_step = p.time_step.is_auto;
  s.t_frac = p.time_step_fraction;
  if (p.time_step.is_auto) {
    s.dt = automatic_step(lightest, s.law, s.t_frac);
  } else {
    s.dt = p.time_step.value;
    if (s.dt > crit)
      throw std::runtime_error(fmt::format("particles.time_step {:.4g} s exceeds the critical step {:.4g} s "
                                           "(seed 000 eq. 2.19): use auto or a smaller step",
                                           s.dt, crit));
    // Two free grains in contact vibrate with their reduced mass, m/2 for a
    // pair of the lightest: eq. 2.19 with it is 1/sqrt(2) of the step above.
    if (const double pair = critical_step(0.5 * lightest, k); s.dt > pair)
      log::warn(
          "particles.time_step {:.4g} s exceeds the critical step {:.4g} s of two of the lightest grains in "
          "contact (seed 000 eq. 2.19 with their reduced mass, m/2): such a contact is unstable; use auto "
          "or a step below it",
          s.dt, pair);
    else if (const double pack = pack_critical_step(lightest, s.law); s.dt > pack)
      log::warn(
          "particles.time_step {:.4g} s exceeds the critical step {:.4g} s of the lightest grain in a dense "
          "pack (12 contacts; 0.109 of eq. 2.19's step when k_S = K_N): grains that pack or pile up will "
          "blow up; use auto (half of it) or a step below it",
          s.dt, pack);
  }
  if (parts.size() == 0) s.dt = 1e-3;
  return s;
}

}  // namespace coflow::particles::dem
