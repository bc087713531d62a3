// The fluid component's schema (keys, defaults, docs, contracts), apart from
// its solvers: the launcher links this alone. fluid/variants.cpp holds the
// solver factories.
#pragma once

#include <vector>

#include "coflow/catalog.hpp"
#include "coflow/registry.hpp"
#include "coflow/run_config.hpp"

namespace coflow::fluid {

class FluidSolver;

// The variants' names, summaries and parameter sections (not "external").
const std::vector<VariantSchema>& variant_schemas();
config::ComponentSchema schema();
// The fluid's part of the pre-run report (fluid/report.cpp).
void report(const config::Config& cfg, const std::string& variant, config::Report& r);

// name -> solver factory. Every variant has one line in register_fluid_variants().
Registry<FluidSolver>& registry();
void register_fluid_variants(Registry<FluidSolver>& r);

}  // namespace coflow::fluid
