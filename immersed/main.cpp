#include <algorithm>
#include <memory>
#include <stdexcept>

#include "coflow/catalog.hpp"
#include "coflow/session.hpp"
#include "immersed/immersed_interface.hpp"
#include "immersed/schema.hpp"

int main(int argc, char** argv) {
  using namespace coflow;
  return coupler::run_component("immersed", argc, argv, catalog(), [](coupler::Session& s) {
    const auto& cfg = s.config();
    const auto& info = cfg.component("immersed");
    const auto names = immersed::registry().names();
    if (std::find(names.begin(), names.end(), info.variant) == names.end())
      throw std::runtime_error("immersed.method '" + info.variant +
                               "' has no built-in implementation yet; run your own executable with "
                               "`coflow run --exe immersed=PATH`");
    const std::string& section = find_variant(immersed::variant_schemas(), info.variant).params_section;
    immersed::ImmersedMethod::Setup setup{cfg, s.decomposition(), s.rank(), s.comm()};
    config::Reader r(cfg.resolved["immersed"][section], cfg.file, "immersed." + section);
    std::unique_ptr<immersed::ImmersedMethod> method = immersed::registry().at(info.variant).create(setup, r);
    r.check();
    method->run(s);
  });
}
