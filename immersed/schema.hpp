// The immersed component's schema (keys, defaults, docs, contracts), apart
// from its methods: the launcher links this alone. immersed/variants.cpp holds
// the method factories.
#pragma once

#include <vector>

#include "coflow/catalog.hpp"
#include "coflow/registry.hpp"
#include "coflow/run_config.hpp"

namespace coflow::immersed {

class ImmersedMethod;

const std::vector<VariantSchema>& variant_schemas();
config::ComponentSchema schema();

// name -> method factory. Every method has one line in register_immersed_variants().
Registry<ImmersedMethod>& registry();
void register_immersed_variants(Registry<ImmersedMethod>& r);

}  // namespace coflow::immersed
