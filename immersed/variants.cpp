#include <algorithm>

#include <fmt/format.h>

#include "immersed/point/point.hpp"
#include "immersed/psm/psm.hpp"
#include "immersed/schema.hpp"

namespace coflow::immersed {

void register_immersed_variants(Registry<ImmersedMethod>& r) {
  r.add<PsmMethod>("psm");
  r.add<PointMethod>("point");
}

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
  // psm: solids into the fluid cells, loads back to the particles, either
  // scheme. point: the fluid at the particles out, their impulses back into the
  // fluid as a momentum source, serial-explicit only (the impulse of a window
  // enters the same window's fluid step).
  s.contract = [](const config::Config&, const std::string& variant) {
    namespace f = config::fields;
    config::Contract c;
    const std::string key = "immersed.method";
    if (variant == "psm") {
      c.provides = {f::solid_fraction, f::hydrodynamic_load};
      c.needs = {{f::solid_force, key, ""}, {f::particle_state, key, ""}};
    }
    if (variant == "point") {
      c.provides = {f::fluid_at_particle, f::momentum_source};
      c.needs = {{f::velocity, key, ""}, {f::particle_state, key, ""}, {f::impulse, key, ""}};
      c.schemes = {config::Scheme::serial_explicit};
    }
    return c;
  };
  s.visit = [s](config::Visitor& v, const config::Config& cfg, config::ComponentInfo& info) {
    config::visit_component_common(v, s, info);
    const auto names = registry().names();
    const bool known = std::find(names.begin(), names.end(), info.variant) != names.end();
    if (v.reading() && !known) {  // point, external, or a wrong name reported above
      v.accept_other_keys();
      return;
    }
    for (const auto& e : registry().entries()) {
      if (e.params_section.empty()) continue;  // a method without parameters (point)
      const bool chosen = v.reading() ? info.variant == e.name : true;
      if (chosen)
        v.section(e.params_section, fmt::format("parameters of method {}", e.name),
                  [&](config::Visitor& sub) { e.visit(sub, v.reading() ? &cfg : nullptr); });
      else if (v.given(e.params_section))
        v.fail(e.params_section, fmt::format("only used with method: {} (this run uses method: {})", e.name,
                                             info.variant));
    }
  };
  return s;
}

}  // namespace coflow::immersed
