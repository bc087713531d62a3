// Every component's configuration schema, for the launcher and the docs
// generator. libcoflow itself names no component: each component's schema
// library defines its `schema_entry()` below, and the `coflow_catalog` library
// (coupler/launcher/catalog.cpp) puts them together. A component built outside
// the tree needs none of this: it links libcoflow alone and reads the file with
// coupler::open_catalog() (the launcher has checked it against this catalogue).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "coflow/registry.hpp"
#include "coflow/run_config.hpp"

namespace coflow {

// What a component's schema library hands the launcher.
struct ComponentEntry {
  config::ComponentSchema schema;
  std::vector<VariantSchema> variants;
};

namespace fluid {
ComponentEntry schema_entry();  // fluid/schema.cpp
}
namespace immersed {
ComponentEntry schema_entry();  // immersed/schema.cpp
}
namespace particles {
ComponentEntry schema_entry();  // particles/schema.cpp
}

const config::Catalog& catalog();

// Variant lists with summaries, for `coflow variants`.
struct VariantInfo {
  std::string component;
  std::string name;
  std::string summary;
  std::string params_section;  // "" when the variant has no subsection
  std::function<void(config::Visitor&)> describe;
};
std::vector<VariantInfo> variant_infos();

}  // namespace coflow
