// The fluid solvers by name; their schemas are in fluid/schema.cpp.
#include "fluid/analytic/analytic_fluid.hpp"
#include "fluid/fv/amr/amr_solver.hpp"
#include "fluid/fv/fv_solver.hpp"
#include "fluid/fv_reference/fv_reference.hpp"
#include "fluid/lbm/lbm_solver.hpp"
#include "fluid/lbm_reference/lbm_reference.hpp"
#include "fluid/schema.hpp"

namespace coflow::fluid {

void register_fluid_variants(Registry<FluidSolver>& r) {
  r.add<LbmSolver>("lbm");
  r.add<LbmReference>("lbm-reference");
  r.add<AnalyticFluid>("analytic");
  // fv on the uniform grid, or on the adaptive one where fluid.fv.refinement is given.
  r.add<fv::FvParams>("fv", [](const FluidSolver::Setup& s, const fv::FvParams& p) -> std::unique_ptr<FluidSolver> {
    if (p.refinement.on) return std::make_unique<fv::amr::AmrFvSolver>(s, p);
    return std::make_unique<FvSolver>(s, p);
  });
  r.add<FvReference>("fv-reference");
}

Registry<FluidSolver>& registry() {
  static Registry<FluidSolver> r = [] {
    Registry<FluidSolver> reg;
    register_fluid_variants(reg);
    return reg;
  }();
  return r;
}

}  // namespace coflow::fluid
