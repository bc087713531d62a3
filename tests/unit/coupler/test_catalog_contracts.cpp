// Every built-in variant states its coupling contract. A component's
// contract() is a function with one branch per variant (docs/architecture.md,
// "Coupling contracts"); a variant added to variants.cpp and schema.cpp
// without its branch would get an empty contract and `coflow validate` would
// let it into any run: this test names it.
#include <catch2/catch.hpp>
#include <string>

#include <yaml-cpp/yaml.h>

#include "coflow/catalog.hpp"
#include "coflow/contract.hpp"
#include "coflow/run_config.hpp"

using namespace coflow;

TEST_CASE("every built-in variant has a contract, and every fluid says what it writes", "[config]") {
  const std::string text = "run: {name: c, end_time: 0.1}\n"
                           "domain: {lower: [0, 0, 0], upper: [1, 1, 1], cells: [8, 8, 8]}\n"
                           "fluid: {solver: analytic, density: 1000, viscosity: 1.0e-6}\n";
  const auto cfg = config::parse_config_node(YAML::Load(text), "contracts.yaml", catalog());
  int checked = 0;
  for (const auto& info : variant_infos()) {
    const config::ComponentSchema* schema = nullptr;
    for (const auto& s : catalog())
      if (s.section == info.component) schema = &s;
    REQUIRE(schema != nullptr);
    REQUIRE(schema->contract);
    INFO(info.component << " variant " << info.name);
    const config::Contract c = schema->contract(cfg, info.name);
    CHECK(c.provides.size() + c.needs.size() > 0);  // what a missing branch gives: nothing
    if (info.component == "fluid") {
      REQUIRE(schema->writes);
      CHECK_FALSE(schema->writes(info.name).empty());
    }
    ++checked;
  }
  CHECK(checked >= 10);  // fluid 5, immersed 3, particles 4 at least
}
