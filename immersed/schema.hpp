#pragma once

#include "coflow/registry.hpp"
#include "coflow/run_config.hpp"
#include "immersed/immersed_interface.hpp"

namespace coflow::immersed {

Registry<ImmersedMethod>& registry();
void register_immersed_variants(Registry<ImmersedMethod>& r);
config::ComponentSchema schema();

}  // namespace coflow::immersed
