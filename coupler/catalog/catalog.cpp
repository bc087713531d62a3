#include "coflow/catalog.hpp"

#include "fluid/schema.hpp"
#include "immersed/schema.hpp"
#include "particles/schema.hpp"

namespace coflow {

const config::Catalog& catalog() {
  static const config::Catalog c{fluid::schema(), immersed::schema(), particles::schema()};
  return c;
}

std::vector<VariantInfo> variant_infos() {
  std::vector<VariantInfo> v;
  for (const auto& e : fluid::registry().entries()) v.push_back({"fluid", e.name, e.summary, e.params_section, e.describe});
  for (const auto& e : immersed::registry().entries()) v.push_back({"immersed", e.name, e.summary, e.params_section, e.describe});
  for (const auto& e : particles::registry().entries()) v.push_back({"particles", e.name, e.summary, e.params_section, e.describe});
  return v;
}

}  // namespace coflow
