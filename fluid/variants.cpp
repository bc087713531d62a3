#include <algorithm>

#include <fmt/format.h>

#include "fluid/analytic/analytic_fluid.hpp"
#include "fluid/lbm/lbm_solver.hpp"
#include "fluid/lbm_reference/lbm_reference.hpp"
#include "fluid/schema.hpp"

namespace coflow::fluid {

void register_fluid_variants(Registry<FluidSolver>& r) {
  r.add<LbmSolver>("lbm");
  r.add<LbmReference>("lbm-reference");
  r.add<AnalyticFluid>("analytic");
}

Registry<FluidSolver>& registry() {
  static Registry<FluidSolver> r = [] {
    Registry<FluidSolver> reg;
    register_fluid_variants(reg);
    return reg;
  }();
  return r;
}

config::ComponentSchema schema() {
  config::ComponentSchema s;
  s.section = "fluid";
  s.selector = "solver";
  s.variants = registry().names();
  s.variants.push_back("external");
  s.doc = "the fluid component (omit the section, or solver: none, for no fluid)";
  // The snapshot fields each variant writes (LbmSolver/LbmReference/AnalyticFluid::fields).
  s.writes = [](const std::string& variant) -> std::vector<std::string> {
    if (variant == "lbm" || variant == "lbm-reference") return {"velocity", "pressure", "density", "solid_fraction"};
    if (variant == "analytic") return {"velocity", "pressure", "density", "vorticity", "k", "epsilon"};
    return {};  // external: its own business
  };
  // lbm takes the solids of psm and returns the force on them; analytic is a
  // prescribed flow (with turbulence) that nothing feeds back into.
  s.contract = [](const config::Config&, const std::string& variant) {
    namespace f = config::fields;
    config::Contract c;
    if (variant == "lbm" || variant == "lbm-reference") c.provides = {f::velocity, f::pressure, f::solid_force};
    if (variant == "analytic") c.provides = {f::velocity, f::pressure, f::k, f::epsilon};
    return c;
  };
  s.visit = [s](config::Visitor& v, const config::Config& cfg, config::ComponentInfo& info) {
    config::visit_component_common(v, s, info);
    const auto names = registry().names();
    const bool known = std::find(names.begin(), names.end(), info.variant) != names.end();
    if (v.reading() && !known) {  // external, none, or a wrong name reported above
      v.accept_other_keys();  // checked by the external executable itself
      return;
    }
    FluidParams p;
    p.visit(v, cfg);
    // One subsection per variant family; only the chosen one may be given.
    std::vector<std::string> done;
    for (const auto& e : registry().entries()) {
      if (e.params_section.empty() ||
          std::find(done.begin(), done.end(), e.params_section) != done.end())
        continue;
      const bool chosen = v.reading() ? registry().at(info.variant).params_section == e.params_section : true;
      if (chosen) {
        const auto& entry = v.reading() ? registry().at(info.variant) : e;
        done.push_back(e.params_section);
        v.section(e.params_section, fmt::format("parameters of solver {}", e.name),
                  [&](config::Visitor& sub) { entry.visit(sub, v.reading() ? &cfg : nullptr); });
      } else if (v.given(e.params_section)) {
        v.fail(e.params_section, fmt::format("only used with solver: {} (this run uses solver: {}); "
                                             "remove the section or change the solver",
                                             e.name, info.variant));
      }
    }
  };
  return s;
}

}  // namespace coflow::fluid
