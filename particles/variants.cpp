#include "particles/schema.hpp"

namespace coflow::particles {

void register_particles_variants(Registry<ParticleSolver>& /*r*/) {}

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
  s.doc = "the particle component: DEM or point particles";
  s.visit = [s](config::Visitor& v, const config::Config&, config::ComponentInfo& info) {
    config::visit_component_common(v, s, info);
    if (v.reading()) v.accept_other_keys();  // the variants' keys arrive with their solvers
  };
  return s;
}

}  // namespace coflow::particles
