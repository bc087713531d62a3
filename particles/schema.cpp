#include "particles/schema.hpp"

#include <algorithm>

#include "particles/particles_interface.hpp"

namespace coflow::particles {

namespace {

// The particle variants read only the common keys (ParticleParams).
struct CommonKeysOnly {
  void visit(config::Visitor&) {}
};

}  // namespace

const std::vector<VariantSchema>& variant_schemas() {
  static const std::vector<VariantSchema> v{
      variant_schema<CommonKeysOnly>(
          "dem", "soft-sphere DEM (Cundall & Strack 1979): linear springs, Coulomb slip, bonds and crushing, cell lists"),
      variant_schema<CommonKeysOnly>("dem-reference", "plain serial soft-sphere DEM, all pairs (the oracle for dem)"),
      variant_schema<CommonKeysOnly>(
          "dpm", "point particles: drag, lift, torque, RK4, hard-sphere collisions found with cell lists"),
      variant_schema<CommonKeysOnly>("dpm-reference",
                                     "plain serial point particles: drag, lift, torque, RK4, hard-sphere "
                                     "collisions over all pairs (the oracle for dpm)"),
  };
  return v;
}

namespace {

bool point_particles(const std::string& variant) { return variant == "dpm" || variant == "dpm-reference"; }

// dem takes forces and torques (psm); dpm takes the fluid at its particles
// and gives back impulses (point), and its Langevin dispersion draws on the
// fluid's k and epsilon (seed 003 eqs 3.35-3.42).
config::Contract contract(const config::Config& cfg, const std::string& variant) {
  namespace f = config::fields;
  config::Contract c;
  const std::string key = "particles.solver";
  if (variant == "dem" || variant == "dem-reference") {
    c.provides = {f::particle_state};
    c.needs = {{f::hydrodynamic_load, key, "immersed"}};
  }
  if (point_particles(variant)) {
    c.provides = {f::particle_state, f::impulse};
    c.needs = {{f::fluid_at_particle, key, "immersed", "or, with immersed.method: ibm, immersed.ibm.particles: point"}};
    c.schemes = {config::Scheme::serial_explicit};
    // The fluid's k and epsilon reach the particles through the point
    // coupling: a run without it (the particles alone) cannot disperse them.
    if (config::resolved_text(cfg, {"particles", "dispersion", "model"}) == "langevin") {
      for (const auto& field : {f::k, f::epsilon})
        c.needs.push_back({field, "particles.dispersion.model", "", "or fluid.solver: fv with fluid.turbulence (k-epsilon), or dispersion.model: none"});
      c.needs.push_back(
          {f::fluid_at_particle, "particles.dispersion.model", "",
           "or dispersion.model: none (the fluid's k and epsilon reach the particles through the "
           "point coupling)"});
    }
  }
  // A species' contact angle: grains wetted by two fluids (dem through psm;
  // point particles are not wetted, so nothing provides it to dpm).
  if (variant == "dem" || variant == "dem-reference" || point_particles(variant)) {
    const YAML::Node species = config::resolved_node(cfg, "particles.species");
    for (const auto& sp : species.IsMap() ? species : YAML::Node()) {
      if (config::resolved_number(cfg, {"particles", "species", sp.first.Scalar(), "contact_angle"}, -1.0) !=
          -1.0)
        c.needs.push_back({f::grain_wetting, "particles.species." + sp.first.Scalar() + ".contact_angle", "",
                           "a contact angle needs resolved grains (particles.solver dem, immersed.method psm) in two fluids "
                           "(fluid.two_phase, fluid.solver lbm or lbm-reference): add those, or leave contact_angle out"});
    }
  }
  return c;
}

// Faces the file leaves out of particles.boundaries (written "" by the
// visitor) are periodic where the domain is, else walls (ParticleParams): the
// resolved file says which.
void resolve(config::Config& cfg, const std::string& variant) {
  if (!has_variant(variant_schemas(), variant)) return;
  const char* faces[] = {"x-", "x+", "y-", "y+", "z-", "z+"};
  YAML::Node b = cfg.resolved["particles"]["boundaries"];
  for (int f = 0; f < 6; ++f) {
    const YAML::Node given = b[faces[f]];
    if (given.IsDefined() && given.IsScalar() && !given.Scalar().empty()) continue;
    b[faces[f]] = cfg.domain.periodic[f / 2] ? "periodic" : "wall";
  }
}

}  // namespace

config::ComponentSchema schema() {
  config::ComponentSchema s = component_schema("particles", "solver", variant_schemas(),
                                                "the particle component: soft-sphere DEM (dem) or point particles (dpm, dpm-reference)");
  s.contract = contract;
  s.report = report;
  s.resolve = resolve;
  s.check = [](config::Visitor& v, const config::Config& cfg, const std::string& variant) {
    if (has_variant(variant_schemas(), variant)) check_step_count(v, cfg, variant);
  };
  s.visit = [s](config::Visitor& v, const config::Config& cfg, config::ComponentInfo& info) {
    config::visit_component_common(v, s, info);
    if (v.reading() && !has_variant(variant_schemas(), info.variant)) {
      v.accept_other_keys();  // external or none: checked by that executable
      return;
    }
    ParticleParams p;
    p.point_particles = point_particles(info.variant);
    p.visit(v, cfg);
    if (v.reading()) p.check_geometry(v, cfg, info);
    if (v.reading() && info.variant == "dpm-reference" && p.dispersion.msd)
      v.fail("dispersion", "dispersion.msd (series/dispersion.csv) is written by dpm; use particles.solver: dpm");
  };
  return s;
}

ComponentEntry schema_entry() { return {schema(), variant_schemas()}; }

}  // namespace coflow::particles
