// The particles component's schema (keys, defaults, docs, contracts), apart
// from its solvers: the launcher links this alone. particles/variants.cpp
// holds the solver factories.
#pragma once

#include <vector>

#include "coflow/catalog.hpp"
#include "coflow/registry.hpp"
#include "coflow/run_config.hpp"

namespace coflow::particles {

class ParticleSolver;

const std::vector<VariantSchema>& variant_schemas();
config::ComponentSchema schema();
// The particles' part of the pre-run report (particles/report.cpp).
void report(const config::Config& cfg, const std::string& variant, config::Report& r);

// name -> solver factory. Every variant has one line in register_particles_variants().
Registry<ParticleSolver>& registry();
void register_particles_variants(Registry<ParticleSolver>& r);

}  // namespace coflow::particles
