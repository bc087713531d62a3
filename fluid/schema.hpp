#pragma once

#include "coflow/registry.hpp"
#include "coflow/run_config.hpp"
#include "fluid/fluid_solver.hpp"

namespace coflow::fluid {

// name -> variant. Every variant has one line in register_fluid_variants().
Registry<FluidSolver>& registry();
void register_fluid_variants(Registry<FluidSolver>& r);
config::ComponentSchema schema();

}  // namespace coflow::fluid
