// The initial particles (particles/dem/initial.cpp): a random fill keeps
// clear of the particles of earlier items in the same region, as it does of
// its own (two overlapping grains at t = 0 push apart with forces of order
// K_N times a radius).
#include <fmt/format.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>

#include "coflow/catalog.hpp"
#include "coflow/log.hpp"
#include "particles/dem/initial.hpp"
#include "particles/particles_interface.hpp"
#include "particles/schema.hpp"

namespace {

// The initial particles dem places for a configuration's text.
coflow::particles::ParticleArrays initial_particles(const char* text) {
  const auto cfg = coflow::config::parse_config_node(YAML::Load(text), "fill.yaml", coflow::catalog());
  coflow::particles::ParticleParams params;
  coflow::config::Reader r(cfg.resolved["particles"], "fill.yaml", "particles");
  params.visit(r, cfg);
  return coflow::particles::dem::make_initial(params, cfg);
}

}  // namespace

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
  const auto a = initial_particles(text);
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

TEST_CASE("a random fill of a log-normal species draws up to its cut-off, not 3 x the mean", "[particles]") {
  // Mean 1 mm, std 1 mm: sigma^2 = ln 2, mu = ln(1e-3) - ln(2) / 2 (seed 003
  // eqs. 4.20-4.21), cut-off mean + 6 std = 7 mm. P(d > 3 mm) = P(Z > (ln 3 +
  // ln(2) / 2) / sqrt(ln 2)) = P(Z > 1.7359) = 0.04129, renormalised by P(d
  // <= 7 mm) = P(Z < 2.7527) = 0.99704: 0.04113 (the normal tail from the
  // complementary error function, computed here). The fill is dilute (solid
  // fraction about 0.2 %), so that a rejected draw (which draws its size
  // anew) hardly favours small grains. Clamping at 3 mm, as before, put none above it.
  const char* text = R"(
run: {name: fill, end_time: 1.0e-3, seed: 7}
domain: {lower: [0, 0, 0], upper: [0.2, 0.2, 0.2], cells: [4, 4, 4]}
particles:
  solver: dem
  species:
    sand: {density: 2650.0, diameter: {lognormal: {mean: 1.0e-3, std: 1.0e-3}}}
  initial:
    - {random: {species: sand, count: 4000, region: {lower: [0, 0, 0], upper: [0.2, 0.2, 0.2]}}}
)";
  const auto a = initial_particles(text);
  REQUIRE(a.size() == 4000);
  long above = 0;
  double largest = 0.0;
  for (double radius : a.radius) {
    above += 2.0 * radius > 3.0e-3;
    largest = std::max(largest, 2.0 * radius);
  }
  const double tail =
      0.5 * std::erfc((std::log(3.0) + 0.5 * std::log(2.0)) / std::sqrt(std::log(2.0)) / std::sqrt(2.0));
  const double kept = 1.0 - 0.5 * std::erfc((std::log(7.0) + 0.5 * std::log(2.0)) / std::sqrt(std::log(2.0)) /
                                            std::sqrt(2.0));
  const double p = tail / kept, n = 4000.0;
  INFO(above << " of 4000 above 3 mm, expected " << p * n << "; the largest " << largest << " m");
  CHECK(std::abs(above - p * n) <= 4.0 * std::sqrt(n * p * (1.0 - p)));  // 4 binomial standard deviations
  CHECK(largest <= 7.0e-3);
}

TEST_CASE("a fixed DEM step past a free pair's or a dense pack's critical step is warned of", "[particles]") {
  // 1 mm grains of 2650 kg/m^3 (m = 1.3875e-6 kg), K = max(K_N, k_S) = 1e4 N/m:
  // eq. 2.19 gives 2 sqrt(m / K) = 2.356e-5 s (refused above); a pair in
  // contact vibrates with the reduced mass m/2: 2 sqrt(m / 2K) = 1.666e-5 s;
  // a grain in 12 contacts at 2 sqrt(m / (12 max(2 K_N, 7 k_S))) = 3.635e-6 s.
  auto warned = [](double step, const std::string& what) {
    const std::string text = fmt::format(R"(
run: {{name: step, end_time: 1.0e-3}}
domain: {{lower: [0, 0, 0], upper: [0.004, 0.004, 0.004], cells: [4, 4, 4]}}
particles:
  solver: dem
  time_step: {}
  species:
    grain: {{density: 2650.0, diameter: 1.0e-3}}
  contact: {{normal_stiffness: 1.0e4, shear_stiffness: 5.0e3, friction: 0.5}}
  initial:
    - {{single: {{species: grain, position: [0.002, 0.002, 0.001]}}}}
)",
                                         step);
    const auto cfg = coflow::config::parse_config_node(YAML::Load(text), "step.yaml", coflow::catalog());
    coflow::particles::ParticleParams params;
    coflow::config::Reader r(cfg.resolved["particles"], "step.yaml", "particles");
    params.visit(r, cfg);
    const auto a = coflow::particles::dem::make_initial(params, cfg);
    auto sink = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(16);
    coflow::log::get()->sinks().push_back(sink);
    const auto setup = coflow::particles::dem::make_setup(params, cfg, a);
    coflow::log::get()->sinks().pop_back();
    CHECK(setup.dt == step);
    bool found = false;
    for (const auto& line : sink->last_formatted()) found = found || line.find(what) != std::string::npos;
    return found;
  };
  const std::string pair = "exceeds the critical step 1.666e-05 s of two of the lightest grains",
                    pack = "exceeds the critical step 3.635e-06 s of the lightest grain in a dense pack";
  CHECK(warned(2.0e-5, pair));
  CHECK(!warned(2.0e-5, pack));  // the stronger warning alone
  CHECK(!warned(1.5e-5, pair));
  CHECK(warned(1.5e-5, pack));
  CHECK(warned(4.0e-6, pack));
  CHECK(!warned(3.5e-6, pack));
}
