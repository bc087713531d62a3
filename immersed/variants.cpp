#include "immersed/schema.hpp"

namespace coflow::immersed {

void register_immersed_variants(Registry<ImmersedMethod>& /*r*/) {}

Registry<ImmersedMethod>& registry() {
  static Registry<ImmersedMethod> r = [] {
    Registry<ImmersedMethod> reg;
    register_immersed_variants(reg);
    return reg;
  }();
  return r;
}

config::ComponentSchema schema() {
  config::ComponentSchema s;
  s.section = "immersed";
  s.selector = "method";
  s.variants = registry().names();
  s.variants.push_back("external");
  s.doc = "the coupling between particles and the fluid grid: psm or point";
  s.visit = [s](config::Visitor& v, const config::Config&, config::ComponentInfo& info) {
    config::visit_component_common(v, s, info);
    if (v.reading()) v.accept_other_keys();  // the variants' keys arrive with their solvers
  };
  return s;
}

}  // namespace coflow::immersed
