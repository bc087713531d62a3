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
struct BoundaryParams;
// The largest |factor| of velocity face `face`'s profile (report.cpp): over
// the face's cell centres, and for a formula in t over up to 65 times in
// [0, run.end_time]; 1 for a uniform face.
double largest_profile_factor(int face, const BoundaryParams& b, const config::Config& cfg);

// name -> solver factory. Every variant has one line in register_fluid_variants().
Registry<FluidSolver>& registry();
void register_fluid_variants(Registry<FluidSolver>& r);

}  // namespace coflow::fluid
