// The initial particles (particles/dem/initial.cpp): a random fill keeps
// clear of the particles of earlier items in the same region, as it does of
// its own (two overlapping grains at t = 0 push apart with forces of order
// K_N times a radius).
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <cmath>

#include "coflow/catalog.hpp"
#include "particles/dem/initial.hpp"
#include "particles/particles_interface.hpp"
#include "particles/schema.hpp"

TEST_CASE("random fills keep clear of the particles of earlier items", "[particles]") {
  // dem_crosscheck's two fills in one region: 1 mm grains, then 1.5 mm ones
  // (wider than the first fill's grid cells), and a 3 mm single among them.
  const char* text = R"(
run: {name: fill, end_time: 1.0e-3}
domain: {lower: [0, 0, 0], upper: [0.012, 0.012, 0.016], cells: [6, 6, 8]}
particles:
  solver: dem
  species:
    big: {density: 2650.0, diameter: 3.0e-3}
    small: {density: 2650.0, diameter: 1.0e-3}
    large: {density: 2650.0, diameter: 1.5e-3}
  initial:
    - {single: {species: big, position: [0.006, 0.006, 0.008]}}
    - {random: {species: small, count: 200, region: {lower: [0, 0, 0], upper: [0.012, 0.012, 0.016]}}}
    - {random: {species: large, count: 100, region: {lower: [0, 0, 0], upper: [0.012, 0.012, 0.016]}}}
)";
  const auto cfg = coflow::config::parse_config_node(YAML::Load(text), "fill.yaml", coflow::catalog());
  coflow::particles::ParticleParams params;
  coflow::config::Reader r(cfg.resolved["particles"], "fill.yaml", "particles");
  params.visit(r, cfg);
  const auto a = coflow::particles::dem::make_initial(params, cfg);
  REQUIRE(a.size() == 301);
  long overlaps = 0;
  double deepest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = i + 1; j < a.size(); ++j) {
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k) d2 += (a.x[3 * i + k] - a.x[3 * j + k]) * (a.x[3 * i + k] - a.x[3 * j + k]);
      const double overlap = a.radius[i] + a.radius[j] - std::sqrt(d2);
      if (overlap > 0) ++overlaps, deepest = std::max(deepest, overlap);
    }
  INFO(overlaps << " overlapping pairs, the deepest " << deepest << " m");
  CHECK(overlaps == 0);
}
