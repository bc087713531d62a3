#include "immersed/schema.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "immersed/ibm/params.hpp"
#include "immersed/point/params.hpp"
#include "immersed/psm/params.hpp"

namespace coflow::immersed {

const std::vector<VariantSchema>& variant_schemas() {
  static const std::vector<VariantSchema> v{
      variant_schema<PsmParams>(
          "psm", "partially saturated cells (Noble & Torczynski 1998), resolved spheres on the fluid grid", "psm"),
      variant_schema<PointParams>("point", "point particles: fluid interpolated at the particles, "
                                           "momentum sources spread back conservatively"),
      variant_schema<IbmParams>("ibm",
                                "immersed boundaries: bodies as closed triangle meshes, fixed or in prescribed "
                                "motion, by multi-direct forcing (seed 003 §4.2.1; Wang, Fan & Luo 2008)",
                                "ibm"),
  };
  return v;
}

namespace {

// psm: solids into the fluid cells, loads back to the particles, either
// scheme. point: the fluid at the particles out, their impulses back into the
// fluid as a momentum source, serial-explicit only (the impulse of a window
// enters the same window's fluid step).
config::Contract contract(const config::Config& cfg, const std::string& variant) {
  namespace f = config::fields;
  config::Contract c;
  const std::string key = "immersed.method";
  if (variant == "psm") {
    c.provides = {f::solid_fraction, f::hydrodynamic_load};
    c.needs = {{f::solid_force, key}, {f::particle_state, key}};
    // The grains' wetting (a contact angle per species) goes to a two-fluid lbm.
    const std::string solver = config::resolved_text(cfg, {"fluid", "solver"});
    if ((solver == "lbm" || solver == "lbm-reference") && config::resolved_node(cfg, "fluid.two_phase").IsMap())
      c.provides.push_back(f::grain_wetting);
  }
  if (variant == "ibm") c.needs = {{f::ibm_forcing, key}};
  // ibm couples point particles where its own key says so (whatever method
  // this run names: the contract of every variant is asked for suggestions).
  const bool ibm_points = config::resolved_text(cfg, {"immersed", "ibm", "particles"}) == "point";
  if (variant == "point" || (variant == "ibm" && ibm_points)) {
    c.provides = {f::fluid_at_particle, f::momentum_source};
    const std::string why = variant == "ibm" ? "immersed.ibm.particles" : key;
    c.needs.insert(c.needs.end(), {{f::velocity, why}, {f::particle_state, why}, {f::impulse, why}});
    c.schemes = {config::Scheme::serial_explicit};
  }
  return c;
}

}  // namespace

// psm, point and ibm read the fluid's density (point also its viscosity)
// from the fluid section, which an external fluid's leaves unchecked: a
// missing or non-numeric value stopped the immersed ranks at their start.
static void check_external_fluid(config::Visitor& v, const config::Config& cfg, const std::string& variant) {
  if (!cfg.has("fluid") || cfg.component("fluid").variant != "external") return;
  if (variant != "psm" && variant != "point" && variant != "ibm") return;
  const bool points =
      variant == "point" || config::resolved_text(cfg, {"immersed", "ibm", "particles"}) == "point";
  for (const char* key : {"density", "viscosity"}) {
    if (std::string(key) == "viscosity" && !points) continue;
    const YAML::Node n = config::resolved_node(cfg, std::string("fluid.") + key);
    double value = 0.0;
    const bool number =
        n.IsScalar() && YAML::convert<double>::decode(n, value) && value > 0.0 && std::isfinite(value);
    if (!number)
      v.fail(
          "immersed.method",
          fmt::format("method {} takes the fluid's {} from fluid.{}, which this run's external fluid "
                      "does not give as a positive number: add fluid.{} ({})",
                      variant, key, key, key, std::string(key) == "density" ? "kg/m^3" : "kinematic, m^2/s"));
  }
}

config::ComponentSchema schema() {
  config::ComponentSchema s = component_schema("immersed", "method", variant_schemas(),
                                                "the coupling between particles and the fluid grid (psm, point), or immersed bodies for the fluid (ibm)");
  s.contract = contract;
  s.check = check_external_fluid;
  s.visit = [s](config::Visitor& v, const config::Config& cfg, config::ComponentInfo& info) {
    config::visit_component_common(v, s, info);
    if (v.reading() && !has_variant(variant_schemas(), info.variant)) {  // external, none, or a wrong name reported above
      v.accept_other_keys();
      return;
    }
    for (const auto& e : variant_schemas()) {
      if (e.params_section.empty()) continue;  // a method without parameters (point)
      const bool chosen = v.reading() ? info.variant == e.name : true;
      if (chosen)
        v.section(e.params_section, fmt::format("parameters of method {}", e.name),
                  [&](config::Visitor& sub) { e.visit(sub, v.reading() ? &cfg : nullptr); });
      else if (v.given(e.params_section)) {
        // Its keys are not reported again as unknown (fluid's solver sections alike).
        v.fail(e.params_section, fmt::format("only used with method: {} (this run uses method: {}); remove "
                                             "the section or change the method",
                                             e.name, info.variant));
        v.section(e.params_section, "", [](config::Visitor& sub) { sub.accept_other_keys(); });
      }
    }
    // psm covers cells with spheres: a grid one cell deep would fold every
    // layer of a sphere into that cell, while its buoyancy and mass stay a
    // sphere's.
    if (v.reading() && info.variant == "psm" && cfg.domain.cells[2] == 1)
      v.fail("method",
             "psm resolves spheres in three dimensions, and this grid is one cell deep "
             "(domain.cells[2] = 1): give the fluid cells along z (D3Q19), or use method: point");
  };
  return s;
}

ComponentEntry schema_entry() { return {schema(), variant_schemas()}; }

}  // namespace coflow::immersed
