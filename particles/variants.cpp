#include <algorithm>

#include "particles/dem/dem_solver.hpp"
#include "particles/dem_reference/dem_reference.hpp"
#include "particles/dpm/dpm_solver.hpp"
#include "particles/dpm_reference/dpm_reference.hpp"
#include "particles/schema.hpp"

namespace coflow::particles {

void register_particles_variants(Registry<ParticleSolver>& r) {
  r.add<DemSolver>("dem");
  r.add<DemReference>("dem-reference");
  r.add<DpmSolver>("dpm");
  r.add<DpmReference>("dpm-reference");
}

Registry<ParticleSolver>& registry() {
  static Registry<ParticleSolver> r = [] {
    Registry<ParticleSolver> reg;
    register_particles_variants(reg);
    return reg;
  }();
  return r;
}

config::ComponentSchema schema() {
  config::ComponentSchema s;
  s.section = "particles";
  s.selector = "solver";
  s.variants = registry().names();
  s.variants.push_back("external");
  s.doc = "the particle component: soft-sphere DEM (dem) or point particles (dpm, dpm-reference)";
  // dem takes forces and torques (psm); dpm takes the fluid at its particles
  // and gives back impulses (point), and its Langevin dispersion draws on the
  // fluid's k and epsilon (seed 003 eqs 3.35-3.42).
  s.contract = [](const config::Config& cfg, const std::string& variant) {
    namespace f = config::fields;
    config::Contract c;
    const std::string key = "particles.solver";
    if (variant == "dem" || variant == "dem-reference") {
      c.provides = {f::particle_state};
      c.needs = {{f::hydrodynamic_load, key, "immersed"}};
    }
    if (variant == "dpm" || variant == "dpm-reference") {
      c.provides = {f::particle_state, f::impulse};
      c.needs = {{f::fluid_at_particle, key, "immersed"}};
      c.schemes = {config::Scheme::serial_explicit};
      if (config::resolved_text(cfg, {"particles", "dispersion", "model"}) == "langevin")
        for (const auto& field : {f::k, f::epsilon}) c.needs.push_back({field, "particles.dispersion.model", "", "or dispersion.model: none"});
    }
    return c;
  };
  s.visit = [s](config::Visitor& v, const config::Config& cfg, config::ComponentInfo& info) {
    config::visit_component_common(v, s, info);
    const auto names = registry().names();
    if (v.reading() && std::find(names.begin(), names.end(), info.variant) == names.end()) {
      v.accept_other_keys();  // external or none: checked by that executable
      return;
    }
    ParticleParams p;
    p.point_particles = info.variant == "dpm" || info.variant == "dpm-reference";
    p.visit(v, cfg);
    if (v.reading()) p.check_geometry(v, cfg, info);
  };
  return s;
}

}  // namespace coflow::particles
