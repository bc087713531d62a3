#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>

#include "coflow/clock.hpp"
#include "coflow/decomposition.hpp"
#include "coflow/output.hpp"
#include "particles/dem/bond_file.hpp"
#include "particles/dem/contact.hpp"
#include "particles/dem/stl.hpp"
#include "particles/dpm/injection.hpp"
#include "particles/dpm/setup.hpp"
#include "particles/particles_interface.hpp"
#include "particles/size_distribution.hpp"

namespace coflow::particles {

using config::Rule;
using config::Visitor;

dem::TriangleMesh load_mesh(const WallParams& w) {
  dem::TriangleMesh m = dem::read_stl(w.mesh.path);
  if (w.scale != 1.0 || w.translate[0] != 0.0 || w.translate[1] != 0.0 || w.translate[2] != 0.0)
    dem::transform(m, w.scale, dem::V3(w.translate[0], w.translate[1], w.translate[2]));
  return m;
}

std::string describe_mesh(const WallParams& w, const dem::TriangleMesh& m) {
  const dem::MeshSummary s = dem::summarize(m);
  const std::string scaled = w.scale != 1.0 ? fmt::format(", scaled by {}", w.scale) : "";
  return fmt::format("{}: {} triangles, box ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g}) m{}, {}",
                     std::filesystem::path(w.mesh.path).filename().string(), s.triangles, s.lower[0], s.lower[1],
                     s.lower[2], s.upper[0], s.upper[1], s.upper[2], scaled,
                     s.closed ? std::string("closed")
                              : fmt::format("open ({} edges of one triangle: a one-sided surface)", s.open_edges));
}

double largest_diameter(const ParticleParams& p) {
  double d = 0.0;
  for (const auto& [name, sp] : p.species) d = std::max(d, largest_diameter(sp.diameter));
  return d;
}

std::string snapshot_shape_error(std::size_t radii, std::size_t positions, std::size_t velocities,
                                 std::size_t angular_velocities, std::size_t species) {
  const std::pair<const char*, std::size_t> sets[] = {
      {"position", positions}, {"velocity", velocities}, {"angular_velocity", angular_velocities}};
  for (const auto& [name, size] : sets)
    if (size != 3 * radii)
      return fmt::format("its dataset {} holds {} values, but {} radii need {} (three a particle)", name,
                         size, radii, 3 * radii);
  if (species != radii)
    return fmt::format("its dataset species holds {} values, but there are {} radii (one a particle)",
                       species, radii);
  return "";
}

int coupling_ghost_cells(const ParticleParams& p, const config::Config& cfg) {
  const double dx = cfg.domain.spacing()[0];
  return static_cast<int>(std::ceil(0.5 * largest_diameter(p) / dx)) + 1;
}

void SpeciesParams::visit(Visitor& v) {
  v.required("density", density, "particle density, kg/m^3", config::positive());
  v.required("diameter", diameter, "diameter in m: fixed, uniform or log-normal", config::positive());
  v("fixed", fixed, "hold these particles in place (they feel forces but keep their initial position and velocity), e.g. a fixed "
    "sphere array");
  v("contact_angle", contact_angle,
    "two-phase fluid with immersed.method psm: the red fluid's contact angle on these grains, degrees; -1: "
    "fluid.two_phase.contact_angle",
    config::Rule{"in [0, 180] or -1", [](const config::ValueRef& r) {
                   const double x = *std::get<double*>(r);
                   return x == -1.0 || (x >= 0.0 && x <= 180.0)
                              ? std::string()
                              : fmt::format("must be in [0, 180] degrees, or -1 for fluid.two_phase.contact_angle "
                                            "(got {})",
                                            x);
                 }});
}

void BondParams::visit(Visitor& v) {
  v.required(
      "compressive_strength", compressive_strength,
      "compressive strength sigma_cC of a bond: it fails when its compressive normal force exceeds sigma_cC "
      "(R1 + R2)^2 (seed 000 eq. 2.15: the square of the radii's sum, not the bond's area), Pa",
      config::non_negative());
  v.required(
      "tensile_strength", tensile_strength,
      "tensile strength sigma_cT of a bond: it fails when its tensile normal force exceeds sigma_cT (R1 + "
      "R2)^2, Pa",
      config::non_negative());
  v.required("shear_strength", shear_strength,
             "shear strength tau_c of a bond: it fails when its shear force exceeds tau_c (R1 + R2)^2, Pa",
             config::non_negative());
  v("crush_fraction", crush_fraction,
    "radius fraction lost by both grains on compressive failure (seed 000 §2.2.2: the crumbled part leaves the "
    "system, so each crushed grain loses 1 - (1 - c)^3 of its mass and momentum; particles.csv's momenta "
    "step down there)",
    config::in_range(0.0, 0.5));
  v("gap", gap,
    "pairs whose surfaces are closer than this at the start are bonded (with pairs: the largest gap a listed "
    "pair may have), m; the normal spring is measured from contact, so a pair bonded across a gap g starts "
    "pulled together by K_N g",
    config::non_negative());
  v("pairs", pairs,
    "CSV file of the bonded pairs (header i,j; particle ids, numbered from 0 in the order of initial), relative "
    "to this file; omit to bond every pair within gap");
}

void ContactParams::visit(Visitor& v) {
  v("normal_stiffness", normal_stiffness, "K_N, stiffness of the linear normal spring of a contact (Cundall & Strack 1979), N/m", config::positive());
  v("shear_stiffness", shear_stiffness, "k_S, stiffness of the tangential spring of a contact (Cundall & Strack 1979), N/m", config::non_negative());
  v("friction", friction, "Coulomb friction coefficient mu: the tangential force is at most mu times the normal one", config::non_negative());
  v("local_damping", local_damping,
    "alpha of the local non-viscous damping: a force -alpha |F| sign(v) on each component of a grain's "
    "motion, F the resultant of the contacts, the fluid and gravity (as PFC and Yade by default; seed 000 "
    "eq. 2.7 leaves gravity out of F, so a free grain falls at (1 - alpha) g here), 0 for none",
    config::in_range(0.0, 0.99));
  v.section(
      "bond",
      "cementation of the initial contacts (bonds that carry tension and shear until they fail); omit for "
      "none",
      [&](Visitor& s) {
        if (s.reading() && !bonded) return;  // its strengths are required only when written
        bond.visit(s);
      },
      &bonded);
}

void CollisionPairParams::visit(Visitor& v) {
  v.required("species", species, "the two species, e.g. [sand, glass] (the same name twice for one species)");
  v("restitution", restitution, "restitution coefficient of this pair", config::in_range(0.0, 1.0));
  v("friction", friction, "dynamic friction coefficient of this pair", config::non_negative());
  if (v.reading() && species.size() != 2) v.fail("species", "give exactly two species names");
}

void CollisionParams::visit(Visitor& v) {
  v("restitution", restitution, "restitution coefficient e: the normal relative speed after a collision over that before", config::in_range(0.0, 1.0));
  v("friction", friction, "dynamic friction coefficient mu_d of the sliding during a collision", config::non_negative());
  v("enabled", enabled, "particle-particle collisions on or off");
  v.list("pairs", "restitution and friction of particular species pairs (the others take the values above)",
         [&](Visitor& s) {
           pairs.emplace_back();
           pairs.back().visit(s);
         });
}

void DispersionParams::visit(Visitor& v) {
  v("model", model, "none, or langevin (Sommerfeld 2001): the fluid velocity seen gets a "
    "fluctuation correlated over T_L = C_T k / epsilon", config::one_of({"none", "langevin"}));
  v("C_T", C_T, "coefficient of the Lagrangian integral time T_L = C_T k / epsilon (seed 003 after eq. 3.38: 2/9, about 0.22, and 0.22 in its runs; 0.26 fits "
    "grid turbulence best, docs/validation.md)", config::positive());
  v.section(
      "msd",
      "dpm: the mean-square lateral displacement of each species after its particles cross a plane (seed 003 eq. "
      "5.24; Snyder & Lumley 1971 reset at x/M = 68.4), into series/dispersion.csv: t (s since each particle's "
      "crossing), msd_<species> (m^2, the mean over the particles and the two lateral axes), n_<species>",
      [&](Visitor& s) {
        if (s.reading() && !msd) return;
        s.required("axis", msd_axis, "the axis the plane is normal to: 0, 1 or 2 (x, y, z)", config::in_range(0, 2));
        s.required("plane", msd_plane, "m: the plane's position along the axis, crossed in the positive direction");
        s.required("interval", msd_interval, "s: between the rows of series/dispersion.csv", config::positive());
        s.required("samples", msd_samples, "rows after the crossing's (t = 0)", config::greater(0));
      },
      &msd);
  if (v.reading() && msd && model != "langevin")
    v.fail("msd", "the displacement statistics are of dispersed particles: set model: langevin");
}

void WallParams::visit(Visitor& v) {
  v("face", face, "a face of the domain as a wall", config::one_of({"", "x-", "x+", "y-", "y+", "z-", "z+"}));
  v("mesh", mesh, "a triangle mesh as a wall: an STL file (ASCII or binary), relative to this file");
  v("restitution", restitution, "restitution coefficient (hard-sphere dpm)", config::in_range(0.0, 1.0));
  // -1 stands for the default (and is how the resolved configuration the
  // components read says so); any other negative value is a mistake.
  config::Rule friction_rule;
  friction_rule.text = ">= 0, or -1";
  friction_rule.test = [](const config::ValueRef& ref) -> std::string {
    const auto* x = std::get_if<double*>(&ref);
    return !x || **x >= 0.0 || **x == -1.0 ? std::string{} : fmt::format("must be >= 0 (got {})", **x);
  };
  v("friction", friction,
    "friction coefficient (-1, the default: the contact's for dem, the collision's for dpm)", friction_rule);
  v("scale", scale, "mesh: factor applied to the file's coordinates (0.001 for a mesh drawn in millimetres)",
    config::positive());
  v("translate", translate, "mesh: shift in m applied after the scale");
  if (v.reading() && (face.empty() == mesh.empty()))
    v.fail("", "give exactly one of face (e.g. face: z-) or mesh (e.g. mesh: plate.stl)");
}

void InjectionParams::visit(Visitor& v) {
  v.required("species", species, "species name");
  v.required("mass_flow", mass_flow, "kg/s; each step injects the particles whose mass the flow has delivered "
             "(the remainder carried to the next step)", config::positive());
  v.required("speed", speed, "m/s", config::positive());
  v("direction", direction, "jet direction (default: the face's normal); e.g. a nozzle angle Phi in the x-y plane "
    "is [cos Phi, sin Phi, 0]");
  v("spread_angle", spread_angle,
    "degrees: directions spread uniformly over the cone of this half-angle about "
    "direction (a nozzle's opening angle, in 3D); with direction's tilt from the normal at most 90",
    config::in_range(0.0, 90.0));
  v("start", start, "s: inject from this time", config::non_negative());
  v("stop", stop, "s: until this time (default: to the end)");
  bool has_disk = false, has_rect = false;
  // (the keys of the face given are checked below: a section's required keys
  // would be demanded of the absent one too)
  bool given[2][3] = {};
  v.section("disk", "a circular inlet face (center, normal and diameter required)", [&](Visitor& s) {
    s("center", center, "m");
    s("normal", normal, "normal, pointing into the domain (normalised)");
    s("diameter", diameter, "m", config::non_negative());
    given[0][0] = s.given("center"), given[0][1] = s.given("normal"), given[0][2] = s.given("diameter");
  }, &has_disk);
  v.section("rectangle", "a rectangular inlet face (center, normal and size required)", [&](Visitor& s) {
    s("center", center, "m");
    s("normal", normal, "normal, pointing into the domain (normalised)");
    s("size", size, "[a, b, 0]: side lengths along axis and along normal x axis, m");
    s("axis", axis, "direction of the first side (default: the coordinate axis most normal to normal)");
    given[1][0] = s.given("center"), given[1][1] = s.given("normal"), given[1][2] = s.given("size");
  }, &has_rect);
  if (!v.reading()) return;
  disk = has_disk;
  if (has_disk == has_rect) {
    v.fail("", "give exactly one of disk or rectangle");
    return;
  }
  const int f = has_disk ? 0 : 1;
  const char* names[2][3] = {{"center", "normal", "diameter"}, {"center", "normal", "size"}};
  for (int k = 0; k < 3; ++k)
    if (!given[f][k]) v.fail(has_disk ? "disk" : "rectangle", fmt::format("missing required key {}", names[f][k]));
  if (has_disk && diameter <= 0.0) v.fail("disk", "diameter must be positive");
  const double nn = normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2];
  if (nn == 0.0) v.fail(has_disk ? "disk" : "rectangle", "normal is the zero vector");
  if (has_rect && given[1][2] && (size[0] <= 0.0 || size[1] <= 0.0)) v.fail("rectangle", "size needs two positive side lengths");
  if (has_rect && (axis[0] * normal[0] + axis[1] * normal[1] + axis[2] * normal[2]) != 0.0 &&
      (axis[0] != 0.0 || axis[1] != 0.0 || axis[2] != 0.0))
    v.fail("rectangle", "axis must be perpendicular to normal");
  const double dn = direction[0] * normal[0] + direction[1] * normal[1] + direction[2] * normal[2];
  if (dn < 0.0) v.fail("direction", "points out of the inlet (against normal)");
  // The cone about direction stays on the inlet's side of its face: a
  // direction tilted from the normal leaves less room for the spread.
  const double dd = direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2];
  const double tilt = dd > 0.0 && nn > 0.0 && dn >= 0.0
                          ? std::acos(std::min(1.0, dn / std::sqrt(dd * nn))) * 180.0 / std::numbers::pi
                          : 0.0;
  if (tilt + spread_angle > 90.0 + 1e-9)
    v.fail("spread_angle",
           fmt::format("a cone of {:.4g} degrees about a direction {:.4g} degrees from the normal "
                       "reaches behind the inlet (particles would start against normal); keep "
                       "the two at 90 degrees or less together",
                       spread_angle, tilt));
  if (stop >= 0.0 && stop <= start) v.fail("stop", "must be later than start");
}

void ParticleParams::visit(Visitor& v, const config::Config& cfg) {
  v("time_step", time_step,
    "s, or auto: dem, the smaller of time_step_fraction x the critical step 2 sqrt(m/K) and half the "
    "critical step of a grain in 12 contacts, shortened as grains crush; dpm, 0.2 x the smallest of "
    "the time to cross the fluid cells' narrowest side, the response time, the mean time between "
    "collisions and, with dispersion, the Lagrangian integral time T_L (seed 003 eq. 4.15), and above "
    "Re_p 55 5 tau_p / (d(f Re_p)/dRe_p), which keeps RK4 stable on the drag; the step a given dpm time_step "
    "makes (the window in whole "
    "steps of at most it) must stay below RK4's limit, 2.785 tau_p (0.836 tau_p with the torque on)",
    config::positive());
  v("time_step_fraction", time_step_fraction, "fraction of the critical step 2 sqrt(m/K) that dem takes with time_step: auto", config::in_range(1e-6, 1.0));
  v.entries("species", "particle kinds by name", [&](const std::string& name, Visitor& s) {
    species.emplace_back(name, SpeciesParams{});
    species.back().second.visit(s);
  });
  if (v.reading() && cfg.resolved.IsMap()) {  // after resolution; while validating, the schema sets it
    const YAML::Node part = cfg.resolved["particles"];
    if (part.IsMap() && part["solver"].IsDefined()) {
      const auto solver = part["solver"].as<std::string>();
      point_particles = solver == "dpm" || solver == "dpm-reference";
    }
  }
  // The keys of one model only: the other model's are an error, and they stay
  // out of the resolved file (docs/config.md lists them all).
  auto only = [&](bool for_points, const std::string& key, const std::function<void()>& visit) {
    if (!v.reading() || for_points == point_particles) {
      visit();
    } else if (v.given(key)) {
      visit();  // read (an error either way), so that the key is not also reported unknown
      v.fail(key, for_points ? fmt::format("{} is for point particles (particles.solver: dpm or dpm-reference)", key)
                             : fmt::format("{} is the soft-sphere contact law of dem; point particles (dpm) collide "
                                           "as hard spheres: use collision",
                                           key));
    }
  };
  only(false, "contact", [&] { v.section("contact", "soft-sphere contact law (dem)", [&](Visitor& s) { contact.visit(s); }); });
  only(true, "collision", [&] {
    v.section("collision", "hard-sphere collisions with restitution and Coulomb friction (dpm)", [&](Visitor& s) { collision.visit(s); });
  });
  only(true, "dispersion",
       [&] { v.section("dispersion", "turbulent dispersion (dpm)", [&](Visitor& s) { dispersion.visit(s); }); });
  only(true, "coupling", [&] {
    v("coupling", coupling,
      "dpm with immersed.method point: two-way (the particles' momentum source acts on the fluid: "
      "particle-source-in-cell, Crowe, Sharma & Stock 1977) or one-way (the fluid does not feel the particles)",
      config::one_of({"two-way", "one-way"}));
  });
  only(true, "forces", [&] {
    v("forces", forces,
      "fluid forces on point particles (dpm): any of gravity_buoyancy, drag (Schiller & Naumann 1933), "
      "saffman_lift (Saffman 1965 with Mei 1992), magnus_lift (Oesterle & Dinh 1998), torque (Dennis et al. 1980)");
    if (v.reading())
      for (const auto& f : forces)
        if (f != "gravity_buoyancy" && f != "drag" && f != "saffman_lift" && f != "magnus_lift" && f != "torque")
          v.fail("forces", fmt::format("unknown force '{}' (known: gravity_buoyancy, drag, saffman_lift, "
                                       "magnus_lift, torque)",
                                       f));
  });
  v.list("walls", "walls: domain faces or triangle meshes", [&](Visitor& s) {
    walls.emplace_back();
    walls.back().visit(s);
  });
  visit_boundaries(v, cfg);
  check_wall_faces(v, cfg);
  visit_initial(v);
  only(true, "injection", [&] {
    v.list("injection",
           "particle inlets (dpm): a mass flow through a disk or a rectangle inside the domain (it may cross "
           "a periodic face)",
           [&](Visitor& s) {
             injection.emplace_back();
             injection.back().visit(s);
           });
  });
  if (!v.reading()) return;
  check_references(v);
  // Grains larger than the box all overlap: check_geometry says the one
  // thing wrong (the grain is larger than the domain), not every pair.
  bool fits = true;
  for (int a = 0; a < 3; ++a)
    fits = fits &&
           (cfg.domain.cells[a] <= 1 || largest_diameter(*this) <= cfg.domain.upper[a] - cfg.domain.lower[a]);
  if (fits) check_initial_overlaps(v);
  check_random_fills(v);
  check_files(v);
  check_time_step(v);
}

void ParticleParams::visit_boundaries(Visitor& v, const config::Config& cfg) {
  v.section("boundaries", "particle boundary per face (default: wall, or periodic where the domain is)",
            [&](Visitor& s) {
              const char* faces[] = {"x-", "x+", "y-", "y+", "z-", "z+"};
              for (int f = 0; f < 6; ++f) {
                s(faces[f], boundaries[f], "outlet | periodic | symmetry | wall",
                  config::one_of({"", "outlet", "periodic", "symmetry", "wall"}));
                if (!s.reading() || boundaries[f].empty()) continue;
                if (boundaries[f] == "symmetry" && !point_particles)
                  s.fail(faces[f], "symmetry faces are for point particles (solver: dpm); dem has outlet, periodic "
                                   "and wall faces");
                const bool per = cfg.domain.periodic[f / 2];
                if ((boundaries[f] == "periodic") != per)
                  s.fail(faces[f], per ? fmt::format("axis {} is periodic (domain.periodic): its faces are periodic",
                                                     "xyz"[f / 2])
                                       : "a periodic particle face needs domain.periodic true on that axis");
              }
            });
}

// A wall item's face must be a wall face: not periodic, and not given another
// kind in particles.boundaries (the solvers made it a wall, but its loads were
// left out of walls.csv, and a periodic axis ignored it).
void ParticleParams::check_wall_faces(Visitor& v, const config::Config& cfg) const {
  if (!v.reading()) return;
  const char* faces[] = {"x-", "x+", "y-", "y+", "z-", "z+"};
  for (std::size_t n = 0; n < walls.size(); ++n)
    for (std::size_t m = 0; m < n; ++m)
      if (!walls[n].face.empty() && walls[m].face == walls[n].face)
        v.fail(fmt::format("walls[{}].face", n),
               fmt::format("face {} is item {} too; give each face once", walls[n].face, m));
  for (std::size_t n = 0; n < walls.size(); ++n)
    for (int f = 0; f < 6; ++f) {
      if (walls[n].face != faces[f]) continue;
      if (cfg.domain.periodic[f / 2])
        v.fail(fmt::format("walls[{}].face", n),
               fmt::format("face {} is periodic (domain.periodic): it has no wall; remove the item "
                           "or make axis {} non-periodic",
                           faces[f], "xyz"[f / 2]));
      else if (!boundaries[f].empty() && boundaries[f] != "wall")
        v.fail(fmt::format("walls[{}].face", n),
               fmt::format("face {} is a wall here and {} {} in particles.boundaries; give the "
                           "face one kind",
                           faces[f], boundaries[f] == "outlet" ? "an" : "a", boundaries[f]));
    }
}

void ParticleParams::visit_initial(Visitor& v) {
  auto region = [](Visitor& s, InitialItem& it) {
    s.section("region", "box to fill", [&](Visitor& r) {
      r.required("lower", it.lower, "lower corner, m");
      r.required("upper", it.upper, "upper corner, m");
    });
  };
  v.choices("initial", "initial particles; each item adds some",
            {{"single", "one particle",
              [&](Visitor& s) {
                auto& it = initial.emplace_back();
                it.kind = "single";
                s.required("species", it.species, "species name");
                s.required("position", it.position, "m");
                s("velocity", it.velocity, "m/s");
                s("angular_velocity", it.angular_velocity, "rad/s");
              }},
             {"lattice", "a simple cubic lattice filling a region",
              [&](Visitor& s) {
                auto& it = initial.emplace_back();
                it.kind = "lattice";
                s.required("species", it.species, "species name");
                s.required("spacing", it.spacing, "lattice spacing, m", config::positive());
                region(s, it);
                s("velocity", it.velocity, "m/s");
              }},
             {"random", "random non-overlapping particles in a region (count or volume fraction)",
              [&](Visitor& s) {
                auto& it = initial.emplace_back();
                it.kind = "random";
                s.required("species", it.species, "species name");
                s("count", it.count, "how many", config::non_negative());
                s("volume_fraction", it.volume_fraction, "or: target solid volume fraction",
                  config::in_range(0.0, 0.6));
                region(s, it);
                s("velocity", it.velocity, "mean velocity, m/s");
                s("velocity_std", it.velocity_std, "standard deviation of each velocity component, m/s",
                  config::non_negative());
                // (A negative count or fraction is refused by its own rule.)
                if (s.reading() && it.count >= 0 && it.volume_fraction >= 0 &&
                    (it.count > 0) == (it.volume_fraction > 0))
                  s.fail("", "give exactly one of count or volume_fraction");
              }},
             {"file", "particles from an HDF5 snapshot written by coflow",
              [&](Visitor& s) {
                auto& it = initial.emplace_back();
                it.kind = "file";
                s.required("path", it.path, "HDF5 file (particles/step_*.h5 of an earlier run), relative to this file");
              }}});
}

std::string ParticleParams::initial_key(std::size_t n, const std::string& field) const {
  return fmt::format("initial[{}].{}{}", n, initial[n].kind, field.empty() ? "" : "." + field);
}

std::string ParticleParams::unknown_species(const std::string& name) const {
  std::vector<std::string> names;
  for (const auto& sp : species) names.push_back(sp.first);
  const std::string near = config::closest(name, names);
  return fmt::format("unknown species '{}'{}; the species defined are: {}", name,
                     near.empty() ? "" : fmt::format(" (did you mean '{}'?)", near), fmt::join(names, ", "));
}

// Every species a key names is defined; fixed particles and injection belong
// to one model each.
void ParticleParams::check_references(Visitor& v) const {
  for (std::size_t n = 0; n < injection.size(); ++n) {
    if (species_index(injection[n].species) < 0)
      v.fail(fmt::format("injection[{}].species", n), unknown_species(injection[n].species));
  }
  for (std::size_t n = 0; n < initial.size(); ++n) {
    const auto& it = initial[n];
    if (it.kind != "file" && species_index(it.species) < 0)
      v.fail(initial_key(n, "species"), unknown_species(it.species));
  }
  for (std::size_t n = 0; n < collision.pairs.size(); ++n)
    for (const auto& name : collision.pairs[n].species)
      if (species_index(name) < 0)
        v.fail(fmt::format("collision.pairs[{}].species", n), unknown_species(name));
  if (point_particles)
    for (const auto& [name, sp] : species)
      if (sp.fixed) v.fail("species", fmt::format("species '{}' is fixed: fixed particles are for dem, not dpm", name));
}

namespace {

// The distance from x to the nearest grain of a lattice item (its centres at
// lower + (i + 1/2) spacing, i < n along each axis, as dem places them): the
// nearest point of a product of grids is the nearest along each axis.
double lattice_distance(const InitialItem& lattice, const std::array<double, 3>& x) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double h = lattice.spacing;
    const long n =
        std::max(1L, static_cast<long>(std::floor((lattice.upper[k] - lattice.lower[k]) / h + 1e-9)));
    const long i = std::clamp(std::lround((x[k] - lattice.lower[k]) / h - 0.5), 0L, n - 1);
    const double c = lattice.lower[k] + (static_cast<double>(i) + 0.5) * h;
    d2 += (x[k] - c) * (x[k] - c);
  }
  return std::sqrt(d2);
}

}  // namespace

// A random fill that cannot be placed: a region narrower than the species'
// smallest grain (every draw was thrown away), or, for grains of one size, a
// solid fraction (given, or count x volume over the region's) beyond the
// 0.38278 at which random sequential addition of equal spheres jams in
// space (Torquato, Uche & Stillinger 2006, Phys. Rev. E 74, 061308; the fill
// keeps grains inside the region, which lowers it further). Before, the
// particles stopped after their ranks started, having tried 1000 draws a grain.
void ParticleParams::check_random_fills(Visitor& v) const {
  constexpr double kRsaJamming = 0.38278;
  for (std::size_t n = 0; n < initial.size(); ++n) {
    const auto& it = initial[n];
    const int k = species_index(it.species);
    if (it.kind != "random" || k < 0) continue;
    const auto& d = species[static_cast<std::size_t>(k)].second.diameter;
    double volume = 1.0;
    for (int a = 0; a < 3; ++a) {
      const double extent = it.upper[a] - it.lower[a];
      volume *= extent;
      if (extent < smallest_diameter(d) && volume > 0) {
        v.fail(initial_key(n, "region"),
               fmt::format(
                   "the region is {} m along {}, narrower than the smallest grain of species '{}' ({} m): "
                   "no grain fits in it; widen the region",
                   config::number(extent), "xyz"[a], it.species, config::number(smallest_diameter(d))));
        volume = 0.0;  // said once; the next item is checked
      }
    }
    if (d.kind != config::Distribution::Kind::fixed || !(volume > 0)) continue;
    const bool by_count = it.count > 0;
    const double fraction = by_count ? it.count * sphere_volume(d.a) / volume : it.volume_fraction;
    if (fraction > kRsaJamming)
      v.fail(initial_key(n, by_count ? "count" : "volume_fraction"),
             fmt::format(
                 "{}a solid fraction of {:.3g} in the region, beyond the {} at which random sequential "
                 "addition of equal spheres jams (and lower beside the region's faces): ask for less, or "
                 "use a lattice",
                 by_count ? fmt::format("{} grains of {} m make ", it.count, config::number(d.a)) : "",
                 fraction, kRsaJamming));
  }
}

// Initial particles may not overlap unless they are to be cemented.
void ParticleParams::check_initial_overlaps(Visitor& v) const {
  auto largest = [&](const std::string& name) {
    const int k = species_index(name);
    if (k < 0) return 0.0;
    return largest_diameter(species[k].second.diameter);  // a log-normal's cut-off, not its mean
  };
  for (std::size_t n = 0; n < initial.size(); ++n) {
    const auto& it = initial[n];
    if (it.kind == "lattice" && it.spacing < largest(it.species) && !contact.bonded)
      v.fail(initial_key(n, "spacing"),
             fmt::format("lattice spacing {:.4g} m is smaller than the diameter {:.4g} m of '{}': "
                         "the particles would overlap; enlarge the spacing",
                         it.spacing, largest(it.species), it.species));
    for (std::size_t m = n + 1; m < initial.size() && it.kind == "lattice"; ++m) {
      const auto& jt = initial[m];  // two lattices filling one place: grains on top of each other
      bool apart = jt.kind != "lattice";
      for (int k = 0; k < 3; ++k)
        apart = apart || std::min(it.upper[k], jt.upper[k]) <= std::max(it.lower[k], jt.lower[k]);
      if (!apart)
        v.fail(initial_key(m, ""),
               fmt::format("items {} and {}: the two lattices' regions overlap, so their grains would "
                           "be placed on (or into) each other; make the regions meet at a face at most",
                           n, m));
    }
    if (it.kind != "single") continue;
    for (std::size_t m = 0; m < initial.size() && !contact.bonded; ++m) {
      const auto& jt = initial[m];  // a single grain in (or next to) a lattice's grains
      if (jt.kind != "lattice") continue;
      const double gap = lattice_distance(jt, it.position),
                   touch = 0.5 * (largest(it.species) + largest(jt.species));
      if (gap < touch)
        v.fail(initial_key(n, "position"),
               fmt::format("items {} and {}: the single grain overlaps a grain of the lattice (centres "
                           "{:.4g} m apart, contact at {:.4g} m); move it, or take the lattice's region "
                           "clear of it",
                           std::min(n, m), std::max(n, m), gap, touch));
    }
    for (std::size_t m = n + 1; m < initial.size(); ++m) {
      const auto& jt = initial[m];
      if (jt.kind != "single") continue;
      double d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += (it.position[k] - jt.position[k]) * (it.position[k] - jt.position[k]);
      const double touch = 0.5 * (largest(it.species) + largest(jt.species));
      if (std::sqrt(d2) < touch && !contact.bonded)
        v.fail(initial_key(m, "position"),
               fmt::format("items {} and {} overlap (centres {:.4g} m apart, contact at {:.4g} m); move "
                           "them apart, or add contact.bond to cement touching grains",
                           n, m, std::sqrt(d2), touch));
    }
  }
}

// The mesh and bond files named must be readable and well formed.
void ParticleParams::check_files(Visitor& v) const {
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const auto& w = walls[i];
    if (w.mesh.empty()) continue;
    const std::string key = fmt::format("walls[{}].mesh", i);
    if (const std::string why = config::file_problem(w.mesh.path); !why.empty()) {
      v.fail(key,
             fmt::format("{}: {} (relative paths are relative to the configuration file)", w.mesh.path, why));
      continue;
    }
    try {
      load_mesh(w);
    } catch (const std::exception& e) {
      v.fail(key, fmt::format("not a usable STL mesh: {}", e.what()));
    }
  }
  if (contact.bonded && !contact.bond.pairs.empty()) {
    try {
      dem::read_bond_csv(contact.bond.pairs.path);
    } catch (const std::exception& e) {
      v.fail("contact.bond.pairs", fmt::format("not a usable bond file: {}", e.what()));
    }
  }
}

// An explicit step beyond the stability limit of seed 000 eq. 2.19 cannot work.
void ParticleParams::check_time_step(Visitor& v) const {
  if (!time_step.is_auto && contact.normal_stiffness > 0 && !point_particles) {
    double crit = 1e300;
    for (const auto& [name, sp] : species) {
      const double d = smallest_diameter(sp.diameter);
      if (!(d > 0)) continue;
      crit = std::min(crit, 2.0 * std::sqrt(sp.density * sphere_volume(d) /
                                            std::max(contact.normal_stiffness, contact.shear_stiffness)));
    }
    if (time_step.value > crit)
      v.fail("time_step", fmt::format("{:.4g} s exceeds the critical step 2 sqrt(m/k) = {:.4g} s of the lightest "
                                      "particle: the integration would be unstable; use auto",
                                      time_step.value, crit));
  }
}

ParticleParams read_particle_params(const config::Config& cfg, const std::string& variant) {
  ParticleParams p;
  p.point_particles = variant == "dpm" || variant == "dpm-reference";
  config::Reader r(cfg.resolved["particles"], cfg.file, "particles");
  p.visit(r, cfg);
  return p;
}

// A given dpm step is not shortened for stability (only the automatic one
// follows seed 003 eq. 4.15; the window is cut into whole steps of at most
// it), and the classical Runge-Kutta method on the drag, du/dt = -u /
// tau_p, is stable only for h < 2.785 tau_p (the real-axis limit of its
// stability region, 1 + z + z^2/2 + z^3/6 + z^4/24 = 1 at z = -2.785):
// beyond it the particles' velocities grow without bound. With the torque
// on, the spin relaxes faster: Stokes' torque pi mu D^3 Omega (seed 003 eq.
// 3.34's 64 pi / Re_r) on I = m D^2 / 10 gives rho_p D^2 / (60 mu) = 0.3
// tau_p. Nonlinear drag (Re_p > 0) only lowers the limits.
// The coupling window the run will take, where validate knows it: given;
// lbm's step (as coupler::output_window shortens it); with no natural step
// (fv, analytic, no fluid), coupler::outputs_window. 0 where an external
// component may offer a shorter step.
static double expected_window(const config::Config& cfg) {
  if (!cfg.coupling.window.is_auto) return cfg.coupling.window.value;
  for (const char* c : {"fluid", "immersed", "particles"})
    if (cfg.has(c) && cfg.component(c).variant == "external") return 0.0;
  const std::string fluid = cfg.has("fluid") ? cfg.component("fluid").variant : "";
  if (fluid == "lbm" || fluid == "lbm-reference") {
    const double tau = config::resolved_number(cfg, {"fluid", "lbm", "tau"}, 0.8),
                 nu = config::resolved_number(cfg, {"fluid", "viscosity"}, 0.0), dx = cfg.domain.spacing()[0];
    return nu > 0 && tau > 0.5 ? coupler::output_window((tau - 0.5) * dx * dx / (3.0 * nu), cfg) : 0.0;
  }
  return coupler::outputs_window(cfg);
}

static void check_point_step(Visitor& v, const config::Config& cfg, const ParticleParams& p) {
  if (!p.point_particles || p.time_step.is_auto) return;
  if (std::find(p.forces.begin(), p.forces.end(), "drag") == p.forces.end()) return;
  const double mu = config::resolved_number(cfg, {"fluid", "density"}, 0.0) *
                    config::resolved_number(cfg, {"fluid", "viscosity"}, 0.0);
  const double window = expected_window(cfg);
  if (!(mu > 0) || !(window > 0)) return;
  // The step taken: the window in whole steps of at most time_step (Clock::substeps).
  const double h = window / std::ceil(window / p.time_step.value - 1e-9);
  constexpr double kRk4RealLimit = 2.785;
  const bool spin = std::find(p.forces.begin(), p.forces.end(), "torque") != p.forces.end();
  for (const auto& [name, sp] : p.species) {
    const double d = smallest_diameter(sp.diameter);
    const double tau = dpm::response_time(sp.density, d, mu), limit = kRk4RealLimit * (spin ? 0.3 : 1.0) * tau;
    if (!(d > 0) || !(h > limit)) continue;
    v.fail(
        "particles.time_step",
        fmt::format(
            "the particles' step, {} s (the coupling window {} s in whole steps of at most this one), "
            "is {:.3g} times the response time tau_p = rho_p D^2 / (18 mu) = {} s of species '{}' (D = {} "
            "m, mu = fluid.density x fluid.viscosity): RK4 is unstable beyond 2.785 times {}; use auto "
            "(0.2 tau_p, seed 003 eq. 4.15) or a step below {} s",
            config::number(h), config::number(window), h / tau, config::number(tau), name, config::number(d),
            spin ? "the spin's response time 0.3 tau_p (the torque is on)" : "it (the drag)",
            config::number(limit)));
    return;
  }
}

// More steps than a run counts (coflow/clock.hpp), from a given step or the
// automatic one, cannot run (after resolution: dpm's estimate needs the fluid).
void check_step_count(Visitor& v, const config::Config& cfg, const std::string& variant) {
  const ParticleParams p = read_particle_params(cfg, variant);
  check_point_step(v, cfg, p);
  const StepEstimate e = p.time_step.is_auto ? automatic_step_estimate(p, cfg, true)
                                             : StepEstimate{p.time_step.value, "", false};
  const double count = cfg.run.end_time / e.step;
  // Grains that only arrive later add sub-steps to their windows (dem::split_for
  // stops a run whose split cannot be counted), not to the start: not refused.
  if (!(e.step > 0) || e.arriving || count <= coupler::kMostWindows) return;
  const std::string why =
      !p.time_step.is_auto ? fmt::format("{} s", config::number(e.step))
      : p.point_particles
          ? fmt::format(
                "auto takes at most {} s at the start (0.2 x the response time rho_p D^2 / (18 mu) of the "
                "largest "
                "grains of species '{}', mu = fluid.density x fluid.viscosity; seed 003 eq. 4.15)",
                config::number(e.step), e.species)
          : fmt::format(
                "auto takes at most {} s at the start (for the largest grains of species '{}': the smaller "
                "of "
                "particles.time_step_fraction x 2 sqrt(m/K), seed 000 eq. 2.19 with K = {} N/m the larger "
                "contact stiffness, and half a dense pack's critical step)",
                config::number(e.step), e.species,
                config::number(std::max(p.contact.normal_stiffness, p.contact.shear_stiffness)));
  const std::string fix =
      !p.time_step.is_auto ? "lengthen the step"
      : p.point_particles  ? "check the species' diameters and densities, fluid.density and fluid.viscosity"
                           : "check the contact stiffnesses against the grains' masses";
  v.fail("particles.time_step",
         fmt::format("{}: {:.3g} steps to run.end_time {} s, more than the {:.0e} a run can count; "
                     "{}, or shorten run.end_time",
                     why, count, config::number(cfg.run.end_time), coupler::kMostWindows, fix));
}

// The species whose grains the run starts with (initial items other than
// files, whose radii are their own); none: those the inlets bring.
static std::vector<int> starting_species(const ParticleParams& p, bool& arriving) {
  std::vector<int> out;
  for (const auto& it : p.initial)
    if (it.kind != "file" && p.species_index(it.species) >= 0) out.push_back(p.species_index(it.species));
  arriving = out.empty();
  if (arriving)
    for (const auto& ip : p.injection)
      if (p.species_index(ip.species) >= 0) out.push_back(p.species_index(ip.species));
  return out;
}

StepEstimate automatic_step_estimate(const ParticleParams& p, const config::Config& cfg, bool largest) {
  StepEstimate e{std::numeric_limits<double>::infinity(), "", false};
  double mu = 0.0;
  if (p.point_particles) {
    const bool drag = std::find(p.forces.begin(), p.forces.end(), "drag") != p.forces.end();
    mu = config::resolved_number(cfg, {"fluid", "density"}, 0.0) *
         config::resolved_number(cfg, {"fluid", "viscosity"}, 0.0);
    if (!drag || !(mu > 0)) return {};
  } else if (!(p.contact.normal_stiffness > 0)) {
    return {};
  }
  const dem::ContactLaw law{p.contact.normal_stiffness, p.contact.shear_stiffness, 0.0, 0.0, 0.0, 0.0};
  bool arriving = false;
  for (const int k : starting_species(p, arriving)) {
    const auto& [name, sp] = p.species[static_cast<std::size_t>(k)];
    const double d = largest ? largest_diameter(sp.diameter) : smallest_diameter(sp.diameter);
    if (!(d > 0)) continue;
    const double step = p.point_particles
                            ? dpm::kLagrangianStepFraction * dpm::response_time(sp.density, d, mu)
                            : dem::automatic_step(sp.density * sphere_volume(d), law, p.time_step_fraction);
    if (step < e.step) e = {step, name, arriving};
  }
  return std::isfinite(e.step) ? e : StepEstimate{};
}

namespace {

bool inside(const Vec3& x, const config::Config& cfg) {
  for (int a = 0; a < 3; ++a)
    if (x[a] < cfg.domain.lower[a] || x[a] > cfg.domain.upper[a]) return false;
  return true;
}

std::string point_text(const Vec3& x) { return fmt::format("({:.4g}, {:.4g}, {:.4g})", x[0], x[1], x[2]); }

std::string domain_text(const config::Config& cfg) {
  return fmt::format("{} to {}", point_text(cfg.domain.lower), point_text(cfg.domain.upper));
}

// How far an inlet's face reaches from its centre along axis a.
double inlet_half_extent(const InjectionParams& ip, int a) {
  using dpm::V3;
  const V3 n = V3(ip.normal.data()).normalized();
  V3 t1, t2;
  dpm::basis(n, V3(ip.axis.data()), t1, t2);
  return ip.disk ? 0.5 * ip.diameter * std::sqrt(std::max(0.0, 1.0 - n[a] * n[a]))
                 : 0.5 * (ip.size[0] * std::abs(t1[a]) + ip.size[1] * std::abs(t2[a]));
}

// How far an inlet's face reaches past the domain along an axis that is not
// periodic (0 or less: it does not); `axis` is where it reaches furthest.
double inlet_overhang(const InjectionParams& ip, const config::Config& cfg, int& axis) {
  double worst = -1e300;
  for (int a = 0; a < 3; ++a) {
    if (cfg.domain.periodic[a]) continue;
    const double e = inlet_half_extent(ip, a);
    const double over =
        std::max(cfg.domain.lower[a] - (ip.center[a] - e), ip.center[a] + e - cfg.domain.upper[a]);
    if (over > worst) worst = over, axis = a;
  }
  return worst;
}

}  // namespace

// A file in a folder that a fresh run into `out` empties before its ranks
// start (the launcher's prepare_run_directory): a snapshot of the same run.
static std::string emptied_folder(const std::string& file, const std::string& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path f = fs::weakly_canonical(fs::absolute(file), ec),
                 o = fs::weakly_canonical(fs::absolute(out), ec);
  for (const char* sub : {"fluid", "particles", "immersed", "series", "events", "logs", "checkpoints"}) {
    const fs::path rel = f.lexically_relative(o / sub);
    if (!rel.empty() && *rel.begin() != "..") return (o / sub).string();
  }
  return {};
}

// The particles of an initial file (a snapshot of another run: perhaps of
// another domain) must be readable, lie in this one's box, belong to a
// species of this run and be no larger than it allows (the ghost layers are
// as wide as a species' largest diameter), and the file must survive the
// start: a fresh run empties its own snapshot folders.
void ParticleParams::check_file_inside(Visitor& v, const config::Config& cfg, std::size_t n) const {
  const auto& it = initial[n];
  if (const std::string folder = emptied_folder(it.path.path, cfg.output_dir()); !folder.empty()) {
    v.fail(initial_key(n, "path"),
           fmt::format("{} lies in {}, which a fresh run into {} empties before it starts: copy "
                       "the file elsewhere, or give this run another run.output.dir",
                       it.path.path, folder, cfg.output_dir()));
    return;
  }
  std::vector<double> x, r, sp;
  try {
    x = output::read_dataset(it.path.path, "position");
    r = output::read_dataset(it.path.path, "radius");
    sp = output::read_dataset(it.path.path, "species");
    const std::string wrong =
        snapshot_shape_error(r.size(), x.size(), output::read_dataset(it.path.path, "velocity").size(),
                             output::read_dataset(it.path.path, "angular_velocity").size(), sp.size());
    if (!wrong.empty()) throw std::runtime_error(wrong);
  } catch (const std::exception& e) {
    v.fail(initial_key(n, "path"),
           fmt::format("cannot read the particles of {}: {}; give a particles/step_*.h5 "
                       "snapshot written by coflow",
                       it.path.path, e.what()));
    return;
  }
  for (std::size_t k = 0; k < r.size() && k < sp.size(); ++k) {
    if (!(sp[k] >= 0 && sp[k] < static_cast<double>(species.size()))) {
      v.fail(initial_key(n, "path"),
             fmt::format("particle {} of {} has species {}, but this run defines {} (0 to {}): "
                         "define the species of the run that wrote it, in its order",
                         k, it.path.path, sp[k], species.size(), species.size() - 1));
      return;
    }
    const auto& [name, s] = species[static_cast<std::size_t>(sp[k])];
    const double largest = particles::largest_diameter(s.diameter);
    if (!(r[k] > 0 && 2.0 * r[k] <= largest * (1.0 + 1e-12))) {
      v.fail(initial_key(n, "path"),
             fmt::format("particle {} of {} has a diameter of {} m, but species '{}' is at most "
                         "{} m: give the species that diameter (or the file smaller grains)",
                         k, it.path.path, config::number(2.0 * r[k]), name, config::number(largest)));
      return;
    }
  }
  std::size_t out = 0, first = 0;
  for (std::size_t k = 0; 3 * k + 2 < x.size(); ++k)
    if (!inside({x[3 * k], x[3 * k + 1], x[3 * k + 2]}, cfg) && out++ == 0) first = k;
  if (out > 0)
    v.fail(initial_key(n, "path"),
           fmt::format("{} of the {} particles of {} lie outside the domain ({}), e.g. particle "
                       "{} at {}; is the file a snapshot of another domain? Give domain its box, or "
                       "move them inside",
                       out, x.size() / 3, it.path.path, domain_text(cfg), first,
                       point_text({x[3 * first], x[3 * first + 1], x[3 * first + 2]})));
}

void ParticleParams::check_geometry(Visitor& v, const config::Config& cfg, const config::ComponentInfo& info) const {
  const auto& d = cfg.domain;
  const double D = largest_diameter(*this);
  const auto h = d.spacing();
  std::array<int, 3> dims{0, 0, 0};
  if (!info.decomposition.is_auto) dims = info.decomposition.value;
  std::array<int, 3> used{1, 1, 1};
  try {
    used = coupler::Decomposition({d.cells[0], d.cells[1], d.cells[2]}, info.ranks, dims, d.periodic).dims();
  } catch (const std::exception&) {
    return;  // the decomposition itself is reported elsewhere
  }
  for (int a = 0; a < 3; ++a) {
    const double extent = d.upper[a] - d.lower[a];
    if (d.cells[a] > 1 && D > extent) {
      v.fail("species", fmt::format("the largest particle ({:.4g} m) is larger than the domain along {} ({:.4g} m): "
                                    "enlarge the domain or use smaller particles",
                                    D, "xyz"[a], extent));
      return;
    }
    // The smallest block along a (cells split as evenly as possible).
    const double block = static_cast<double>(d.cells[a] / used[a]) * h[a];
    if (used[a] > 1 && D > block)
      v.fail("ranks", fmt::format("{} ranks cut {} into blocks of {:.4g} m, smaller than the largest particle ({:.4g} "
                                  "m), whose contacts would then reach past the neighbouring blocks: use at most {} "
                                  "blocks along {} (particles.ranks or particles.decomposition)",
                                  info.ranks, "xyz"[a], block, D, std::max(1L, static_cast<long>(extent / D)), "xyz"[a]));
  }
  for (std::size_t n = 0; n < initial.size(); ++n) {
    const auto& it = initial[n];
    if (it.kind == "single" && !inside(it.position, cfg))
      v.fail(initial_key(n, "position"), fmt::format("position {} is outside the domain ({}); move it inside",
                                                     point_text(it.position), domain_text(cfg)));
    if ((it.kind == "lattice" || it.kind == "random") &&
        !(it.lower[0] < it.upper[0] && it.lower[1] < it.upper[1] && it.lower[2] < it.upper[2]))
      v.fail(initial_key(n, "region.upper"),
             fmt::format("region {} to {} is empty: each of upper's coordinates must exceed "
                         "lower's",
                         point_text(it.lower), point_text(it.upper)));
    else if ((it.kind == "lattice" || it.kind == "random") &&
             (!inside(it.lower, cfg) || !inside(it.upper, cfg)))
      v.fail(initial_key(n, "region.lower"),
             fmt::format("region {} to {} reaches outside the domain ({}); keep it inside",
                         point_text(it.lower), point_text(it.upper), domain_text(cfg)));
    if (it.kind == "file") check_file_inside(v, cfg, n);
  }
  for (std::size_t n = 0; n < injection.size(); ++n) {
    int a = 0;
    const double over = inlet_overhang(injection[n], cfg, a);
    if (!inside(injection[n].center, cfg))
      v.fail(fmt::format("injection[{}].{}.center", n, injection[n].disk ? "disk" : "rectangle"),
             fmt::format("centre {} is outside the domain ({}); particles would enter nowhere",
                         point_text(injection[n].center), domain_text(cfg)));
    else if (over > 1e-9 * (cfg.domain.upper[a] - cfg.domain.lower[a]))
      v.fail(fmt::format("injection[{}].{}", n, injection[n].disk ? "disk" : "rectangle"),
             fmt::format("the {} reaches {:.4g} m past the domain ({}) along {}, which is not "
                         "periodic: particles would enter outside it; move the inlet or make it smaller",
                         injection[n].disk ? "disk" : "rectangle", over, domain_text(cfg), "xyz"[a]));
    for (int k = 0; k < 3; ++k) {
      const double L = cfg.domain.upper[k] - cfg.domain.lower[k],
                   span = 2.0 * inlet_half_extent(injection[n], k);
      if (cfg.domain.periodic[k] && span > L * (1.0 + 1e-9))
        v.fail(fmt::format("injection[{}].{}", n, injection[n].disk ? "disk" : "rectangle"),
               fmt::format("the {} spans {:.4g} m along {}, more than the domain's period "
                           "({:.4g} m): parts of it would fall on each other; make it smaller",
                           injection[n].disk ? "disk" : "rectangle", span, "xyz"[k], L));
    }
  }
  check_meshes_inside(v, cfg);
}

void ParticleParams::check_meshes_inside(Visitor& v, const config::Config& cfg) const {
  for (std::size_t n = 0; n < walls.size(); ++n) {
    if (walls[n].mesh.empty()) continue;
    dem::TriangleMesh m;
    try {
      m = load_mesh(walls[n]);
    } catch (const std::exception&) {
      continue;  // reported by visit()
    }
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& x : m.vertices)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], x[a]);
        hi[a] = std::max(hi[a], x[a]);
      }
    bool overlaps = !m.vertices.empty();
    for (int a = 0; a < 3; ++a) overlaps = overlaps && hi[a] >= cfg.domain.lower[a] && lo[a] <= cfg.domain.upper[a];
    if (!overlaps)
      v.fail(fmt::format("walls[{}].mesh", n),
             fmt::format("the mesh {} spans {} to {}, entirely outside the domain ({}); is it in "
                         "other units or another frame?",
                         walls[n].mesh.path, point_text(lo), point_text(hi), domain_text(cfg)));
  }
}

int ParticleParams::species_index(const std::string& name) const {
  for (std::size_t i = 0; i < species.size(); ++i)
    if (species[i].first == name) return static_cast<int>(i);
  return -1;
}

}  // namespace coflow::particles
