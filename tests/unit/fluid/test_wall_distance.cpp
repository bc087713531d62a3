// The k-epsilon model's distance to immersed bodies from their markers
// (fluid/fv/turbulence/wall_distance.hpp): against the exact distance to a
// circle (2D) and a sphere (3D) sampled about a cell apart, a segment's end,
// retracted markers and a periodic box; the k-d tree's nearest marker
// against a search of every marker.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "fluid/fv/turbulence/wall_distance.hpp"
#include "tests/unit/worst.hpp"

using namespace coflow;

namespace {

constexpr double kPi = std::numbers::pi;

// A marker of a piece of surface of `area` (h the cell's sides, 2D or 3D as
// ibm::GridGeometry takes Delta V_Gamma = area x shell).
ibm::Marker marker(const ibm::Vec& x, const ibm::Vec& n, double area, const std::array<double, 3>& h, int dims) {
  const ibm::GridGeometry g{{0, 0, 0}, {1, 1, 1}, {h[0], h[1], h[2]}, dims};
  ibm::Marker m;
  m.x = x;
  m.n = n;
  m.volume_ratio = area * g.shell() / g.cell_volume();
  return m;
}

// A box of [-5, 5]^3 around the bodies, not periodic.
fluid::fv::BodyDistance::Grid grid(const std::array<double, 3>& h, int dims) {
  fluid::fv::BodyDistance::Grid g;
  g.h = h;
  g.lower = {-5, -5, -5};
  g.upper = {5, 5, 5};
  g.dims = dims;
  return g;
}

}  // namespace

TEST_CASE("body distance: a circle sampled a cell apart (2D)", "[fv][k-epsilon]") {
  const std::array<double, 3> h{0.1, 0.1, 0.1};
  const double R = 1.0;
  const int count = 63;  // spacing 2 pi R / 63 = 0.0997
  ibm::MarkerSet set;
  for (int k = 0; k < count; ++k) {
    const double th = 2 * kPi * k / count;
    set.markers.push_back(marker({R * std::cos(th), R * std::sin(th), 0.7 * k}, {std::cos(th), std::sin(th), 0.0},
                                 2 * kPi * R / count * h[2], h, 2));  // z ignored in 2D
  }
  const fluid::fv::BodyDistance distance(set, grid(h, 2));
  double worst = 0.0;
  for (double r : {0.45, 0.93, 0.99, 1.01, 1.05, 1.3, 2.0, 4.0})
    for (int a = 0; a < 17; ++a) {
      const double th = 0.37 + 2 * kPi * a / 17;
      worst = coflow::test::worst_of(
          worst, std::abs(distance({r * std::cos(th), r * std::sin(th), 3.0}) - std::abs(r - R)));
    }
  // A chord's sagitta, s^2 / (8 R) = 1.2e-3, bounds the error of a tangent
  // segment over its piece of arc.
  CHECK(worst < 1.5e-3);
}

TEST_CASE("body distance: a 2D marker is a segment of its length, retracted markers go back",
          "[fv][k-epsilon]") {
  const std::array<double, 3> h{0.1, 0.1, 0.1};
  ibm::MarkerSet set;  // a segment 0.4 long on y = 0, facing +y
  set.markers.push_back(marker({0, 0, 0}, {0, 1, 0}, 0.4 * h[2], h, 2));
  const fluid::fv::BodyDistance distance(set, grid(h, 2));
  CHECK(distance({0.15, 0.1, 0}) == Approx(0.1));                  // over the segment
  CHECK(distance({0.5, 0.1, 0}) == Approx(std::hypot(0.1, 0.3)));  // 0.3 beyond its end
  // The same marker retracted by 0.3 cells (0.03 m) into the body: put back.
  set.markers[0].x[1] = -0.03;
  auto g = grid(h, 2);
  g.retraction = 0.3;
  CHECK(fluid::fv::BodyDistance(set, g)({0.15, 0.1, 0}) == Approx(0.1));
}

TEST_CASE("body distance: periodic axes wrap the markers and see across the faces", "[fv][k-epsilon]") {
  const std::array<double, 3> h{0.1, 0.1, 0.1};
  ibm::MarkerSet set;  // a marker just inside x+ = 5, and one 0.3 past it (a body that crossed)
  set.markers.push_back(marker({4.9, 0, 0}, {1, 0, 0}, 0.01, h, 3));
  set.markers.push_back(marker({5.3, 2, 0}, {1, 0, 0}, 0.01, h, 3));
  auto g = grid(h, 3);
  CHECK(fluid::fv::BodyDistance(set, g)({-4.9, 0, 0}) == Approx(9.8));  // not periodic: across the box
  g.periodic[0] = true;
  const fluid::fv::BodyDistance distance(set, g);
  CHECK(distance({-4.9, 0, 0}) == Approx(0.2));  // through x+- = +-5
  CHECK(distance({-4.6, 2, 0}) == Approx(0.1));  // the crossed marker, wrapped to -4.7
}

TEST_CASE("body distance: a sphere sampled a cell apart (3D)", "[fv][k-epsilon]") {
  const std::array<double, 3> h{0.1, 0.1, 0.1};
  const double R = 1.0;
  const int count = 1257;  // 4 pi R^2 / h^2 markers: a Fibonacci sphere
  ibm::MarkerSet set;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < count; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / count, rho = std::sqrt(1.0 - z * z), phi = golden * k;
    const ibm::Vec n{rho * std::cos(phi), rho * std::sin(phi), z};
    set.markers.push_back(marker({R * n[0], R * n[1], R * n[2]}, n, 4 * kPi * R * R / count, h, 3));
  }
  const fluid::fv::BodyDistance distance(set, grid(h, 3));
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int k = 0; k < 400; ++k) {
    ibm::Vec d{u(gen), u(gen), u(gen)};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double r = 0.4 + 2.0 * (k % 20) / 20.0;
    const std::array<double, 3> x{r * d[0] / len, r * d[1] / len, r * d[2] / len};
    worst = coflow::test::worst_of(worst, std::abs(distance(x) - std::abs(r - R)));
  }
  // About h^2 / R: the pieces' squares over a curved surface.
  CHECK(worst < 1e-2);
}

TEST_CASE("body distance: the k-d tree finds the nearest marker", "[fv][k-epsilon]") {
  const std::array<double, 3> h{0.1, 0.1, 0.1};
  for (int dims : {2, 3}) {
    std::mt19937 gen(11);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    ibm::MarkerSet set;
    for (int k = 0; k < 500; ++k)
      set.markers.push_back(marker({u(gen), u(gen), u(gen)}, {0, 0, 0}, 0.01, h, dims));
    const fluid::fv::BodyDistance distance(set,
                                           grid(h, dims));  // no normals: the distance to the nearest point
    for (int q = 0; q < 300; ++q) {
      const std::array<double, 3> x{1.5 * u(gen), 1.5 * u(gen), 1.5 * u(gen)};
      double best = 1e300;
      for (const auto& m : set.markers)
        best = std::min(best, std::hypot(x[0] - m.x[0], x[1] - m.x[1], dims == 3 ? x[2] - m.x[2] : 0.0));
      REQUIRE(distance(x) == Approx(best).epsilon(1e-14));
    }
  }
  CHECK(std::isinf(fluid::fv::BodyDistance(ibm::MarkerSet{}, grid(h, 3))({0, 0, 0})));
}
