// Every component's configuration schema, for the launcher and for each
// executable (every executable validates the whole file).
#pragma once

#include "coflow/run_config.hpp"

namespace coflow {

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
