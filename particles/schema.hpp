#pragma once

#include "coflow/registry.hpp"
#include "coflow/run_config.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles {

// name -> variant. Every variant has one line in register_particles_variants().
Registry<ParticleSolver>& registry();
void register_particles_variants(Registry<ParticleSolver>& r);
config::ComponentSchema schema();

}  // namespace coflow::particles
