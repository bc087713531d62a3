// The point method's stencil (immersed/point/stencil.hpp): trilinear
// interpolation is exact on linear fields, the weights add up to one (so
// spreading a particle's impulse conserves it), and next to a wall the
// clamped stencil stays in the domain and still conserves.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "immersed/point/stencil.hpp"

using namespace coflow;

namespace {
config::DomainParams box(bool periodic) {
  config::DomainParams d;
  d.lower = {0.0, 0.0, 0.0};
  d.upper = {1.0, 1.0, 1.0};
  d.cells = {10, 10, 10};
  d.periodic = {periodic, periodic, periodic};
  return d;
}
}  // namespace

TEST_CASE("trilinear interpolation reproduces a linear field exactly", "[immersed][point]") {
  const auto d = box(false);
  const double h = 0.1;
  auto field = [](double x, double y, double z) { return 1.5 - 2.0 * x + 0.25 * y + 3.0 * z; };
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.05, 0.95);  // between the first and last cell centres
  for (int n = 0; n < 1000; ++n) {
    const double x[3] = {u(rng), u(rng), u(rng)};
    const immersed::Stencil st = immersed::stencil(x, d, h);
    double value = 0.0, wsum = 0.0;
    for (int c = 0; c < 8; ++c) {
      const auto& i = st.cell[c];
      value += st.weight[c] * field((i[0] + 0.5) * h, (i[1] + 0.5) * h, (i[2] + 0.5) * h);
      wsum += st.weight[c];
    }
    CHECK(std::abs(value - field(x[0], x[1], x[2])) < 1e-13);
    CHECK(std::abs(wsum - 1.0) < 1e-15);
  }
}

TEST_CASE("spreading conserves: weights add up to one, also against walls and across periodic faces",
          "[immersed][point]") {
  for (bool periodic : {false, true}) {
    const auto d = box(periodic);
    for (const auto& p : {std::array<double, 3>{0.01, 0.5, 0.5}, std::array<double, 3>{0.99, 0.02, 0.97},
                          std::array<double, 3>{0.5, 0.5, 0.5}}) {
      const immersed::Stencil st = immersed::stencil(p.data(), d, 0.1);
      double wsum = 0.0;
      for (int c = 0; c < 8; ++c) {
        wsum += st.weight[c];
        CHECK(st.weight[c] >= 0.0);
        for (int a = 0; a < 3; ++a) {
          if (!periodic) CHECK((st.cell[c][a] >= 0 && st.cell[c][a] <= 9));
          if (periodic) CHECK((st.cell[c][a] >= -1 && st.cell[c][a] <= 10));  // the exchange wraps them
        }
      }
      CHECK(std::abs(wsum - 1.0) < 1e-15);
    }
  }
}
