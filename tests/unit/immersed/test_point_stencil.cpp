// The point method's stencil (immersed/point/stencil.hpp): trilinear
// interpolation is exact on linear fields, the weights add up to one (so
// spreading a particle's impulse conserves it), and next to a wall the
// clamped stencil stays in the domain and still conserves; cells that are not
// cubes, an axis of one cell, and a point that rounds onto a periodic face.
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
    const immersed::Stencil st = immersed::stencil(x, d, {h, h, h});
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

TEST_CASE("interpolation stays exact for a linear field up to the faces (extrapolate)", "[immersed][point]") {
  // Within half a cell of a face the clamped stencil gives the first cell's
  // value (u = S y at y = h/4 read S h/2); the extrapolating one follows the
  // line through the two nearest centres, and stays inside the domain.
  const auto d = box(false);
  const double h = 0.1;
  auto field = [](double x, double y, double z) { return 1.5 - 2.0 * x + 0.25 * y + 3.0 * z; };
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> near(0.0, 0.05), any(0.0, 1.0);
  double clamped_worst = 0.0;
  for (int n = 0; n < 1000; ++n) {
    double x[3] = {any(rng), any(rng), any(rng)};
    const int axis = n % 3;
    x[axis] = n % 2 ? near(rng) : 1.0 - near(rng);  // between a face and the nearest centre
    const immersed::Stencil st = immersed::stencil(x, d, {h, h, h}, true);
    const immersed::Stencil cl = immersed::stencil(x, d, {h, h, h});
    double value = 0.0, clamped = 0.0, wsum = 0.0;
    for (int c = 0; c < 8; ++c) {
      const auto& i = st.cell[c];
      const auto& j = cl.cell[c];
      for (int a = 0; a < 3; ++a) CHECK((i[a] >= 0 && i[a] <= 9));
      value += st.weight[c] * field((i[0] + 0.5) * h, (i[1] + 0.5) * h, (i[2] + 0.5) * h);
      clamped += cl.weight[c] * field((j[0] + 0.5) * h, (j[1] + 0.5) * h, (j[2] + 0.5) * h);
      wsum += st.weight[c];
    }
    CHECK(std::abs(value - field(x[0], x[1], x[2])) < 1e-13);
    CHECK(std::abs(wsum - 1.0) < 1e-14);
    clamped_worst = std::max(clamped_worst, std::abs(clamped - field(x[0], x[1], x[2])));
  }
  CHECK(clamped_worst > 0.01);  // the clamped stencil is not exact there (so the case tests something)
}

TEST_CASE("spreading conserves: weights add up to one, also against walls and across periodic faces",
          "[immersed][point]") {
  for (bool periodic : {false, true}) {
    const auto d = box(periodic);
    for (const auto& p : {std::array<double, 3>{0.01, 0.5, 0.5}, std::array<double, 3>{0.99, 0.02, 0.97},
                          std::array<double, 3>{0.5, 0.5, 0.5}}) {
      const immersed::Stencil st = immersed::stencil(p.data(), d, {0.1, 0.1, 0.1});
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

TEST_CASE("the stencil takes each axis's own spacing, and an axis of one cell", "[immersed][point]") {
  config::DomainParams d;
  d.lower = {0.0, 0.0, 0.0};
  d.upper = {1.0, 0.5, 0.25};
  d.cells = {10, 10, 10};  // 0.1 x 0.05 x 0.025 m cells
  d.periodic = {false, false, false};
  const config::Vec3 h = d.spacing();
  auto field = [](double x, double y, double z) { return 1.5 - 2.0 * x + 0.25 * y + 3.0 * z; };
  const double x[3] = {0.43, 0.31, 0.117};
  immersed::Stencil st = immersed::stencil(x, d, h);
  double value = 0.0;
  for (int c = 0; c < 8; ++c) {
    const auto& i = st.cell[c];
    value += st.weight[c] * field((i[0] + 0.5) * h[0], (i[1] + 0.5) * h[1], (i[2] + 0.5) * h[2]);
  }
  CHECK(std::abs(value - field(x[0], x[1], x[2])) < 1e-13);
  // One periodic cell along z (a flat D3Q19 lattice): every weight on z = 0.
  d.upper = {1.0, 1.0, 0.1};
  d.cells = {10, 10, 1};
  d.periodic = {false, false, true};
  for (const double z : {0.0, 0.03, 0.05, 0.0999}) {
    const double p[3] = {0.43, 0.31, z};
    st = immersed::stencil(p, d, d.spacing());
    double wsum = 0.0;
    for (int c = 0; c < 8; ++c) {
      CHECK(st.cell[c][2] == 0);
      wsum += st.weight[c];
    }
    CHECK(std::abs(wsum - 1.0) < 1e-15);
  }
}

TEST_CASE("a point that rounds onto a periodic face keeps its stencil beside the cell it is routed to",
          "[immersed][point]") {
  // 0.8999999999999999 / 0.18 is 5.0 in doubles: the point exchange routes the
  // point to cell floor(5.0) = 5, wrapped to 0; the stencil must lie within
  // one cell of it (cells -1 and 0), not at cells 4 and 5.
  config::DomainParams d;
  d.lower = {0.0, 0.0, 0.0};
  d.upper = {0.9, 0.9, 0.9};
  d.cells = {5, 5, 5};
  d.periodic = {true, true, true};
  const config::Vec3 h = d.spacing();
  const double x[3] = {std::nextafter(0.9, 0.0), 0.45, 0.45};
  REQUIRE(std::floor((x[0] - d.lower[0]) / h[0]) == 5.0);
  const immersed::Stencil st = immersed::stencil(x, d, h);
  for (int c = 0; c < 8; ++c) CHECK((st.cell[c][0] == -1 || st.cell[c][0] == 0));
}
