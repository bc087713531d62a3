// Snapshot numbers: snapshot k is at time k x run.output.every whatever the
// window (which, in a run without a fluid, follows the series interval), and
// the final one, at an end time between two multiples, comes next.
#include <catch2/catch.hpp>

#include "coflow/catalog.hpp"
#include "coflow/clock.hpp"
#include "coflow/config.hpp"

using namespace coflow;

namespace {
config::Config particles_only(const std::string& series_every) {
  const std::string text = R"(
run: {name: demo, end_time: 0.85, output: {every: 0.1, series_every: )" + series_every + R"(}}
domain: {lower: [0, 0, 0], upper: [0.01, 0.01, 0.01], cells: [4, 4, 4]}
particles:
  solver: dem
  species: {glass: {density: 2500.0, diameter: 1.0e-3}}
  initial: [{single: {species: glass, position: [0.005, 0.005, 0.005]}}]
)";
  return config::parse_config_node(YAML::Load(text), "c.yaml", coflow::catalog());
}
}  // namespace

TEST_CASE("snapshot numbers count multiples of output.every, whatever the window", "[config]") {
  for (const char* series : {"0.005", "0.001", "0.1"}) {
    const config::Config cfg = particles_only(series);
    coupler::Clock clock(cfg, 0, 0.0, "");
    const double window = clock.negotiate(0.0);
    INFO("series_every " << series << ", window " << window);
    long last = -1, written = 0;
    for (long w = 0; w <= clock.windows(); ++w) {
      if (!clock.snapshot_due(w)) continue;
      const long k = clock.snapshot_number(w);
      CHECK(k == last + 1);  // no gaps, no repeats
      if (w < clock.windows()) CHECK(std::abs(w * window - 0.1 * k) < 1e-9);
      last = k;
      ++written;
    }
    CHECK(written == 10);  // 0, 0.1, ..., 0.8 and the end, 0.85
    CHECK(last == 9);
  }
}
