#include <algorithm>
#include <memory>
#include <stdexcept>

#include "coflow/catalog.hpp"
#include "coflow/session.hpp"
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
    const auto& entry = immersed::registry().at(info.variant);
    immersed::ImmersedMethod::Setup setup{cfg, s.decomposition(), s.rank(), s.comm()};
    config::Reader r(cfg.resolved["immersed"][entry.params_section], cfg.file, "immersed." + entry.params_section);
    std::unique_ptr<immersed::ImmersedMethod> method = entry.create(setup, r);
    r.check();
    method->run(s);
  });
}
