#include "coflow/catalog.hpp"

namespace coflow {

namespace {

const std::vector<ComponentEntry>& entries() {
  static const std::vector<ComponentEntry> e{fluid::schema_entry(), immersed::schema_entry(),
                                             particles::schema_entry()};
  return e;
}

}  // namespace

const config::Catalog& catalog() {
  static const config::Catalog c = [] {
    config::Catalog out;
    for (const auto& e : entries()) out.push_back(e.schema);
    return out;
  }();
  return c;
}

std::vector<VariantInfo> variant_infos() {
  std::vector<VariantInfo> out;
  for (const auto& e : entries())
    for (const auto& v : e.variants)
      out.push_back({e.schema.section, v.name, v.summary, v.params_section,
                     [visit = v.visit](config::Visitor& d) { visit(d, nullptr); }});
  return out;
}

}  // namespace coflow
