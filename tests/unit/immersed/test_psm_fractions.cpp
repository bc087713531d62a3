// psm's solid fractions (immersed/psm): exact cases of the octree (cells wholly
// inside or outside, a plane through leaf boundaries), and the volume of a
// sphere summed over the grid against 4/3 pi r^3 as the octree refines.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include "immersed/psm/fractions.hpp"
#include "tests/unit/worst.hpp"

using coflow::immersed::cube_fraction;
using V = std::array<double, 3>;

TEST_CASE("octree fractions are exact where the answer is 0, 1 or a half", "[immersed][psm]") {
  const V lo{0, 0, 0};
  // A small sphere at the centre holds the 8 innermost of the 8^3 leaf centres
  // (sqrt(3)/16 = 0.108 from it): 8/512 exactly; below that radius it holds none.
  CHECK(cube_fraction(lo, 1.0, {0.5, 0.5, 0.5}, 0.15, 3) == 8.0 / 512.0);
  CHECK(cube_fraction(lo, 1.0, {0.5, 0.5, 0.5}, 0.1, 3) == 0.0);
  CHECK(cube_fraction(lo, 1.0, {0.5, 0.5, 0.5}, 2.0, 3) == 1.0);   // the cube is inside
  CHECK(cube_fraction(lo, 1.0, {5.0, 5.0, 5.0}, 1.0, 3) == 0.0);   // far outside
  CHECK(cube_fraction(lo, 1.0, {1.5, 0.5, 0.5}, 0.49, 3) == 0.0);  // just outside, across a face
  // A sphere so large that its surface through the cube's mid-plane is flat to
  // round-off: the plane falls between leaf centres at every level, so half the
  // leaves count, exactly.
  const double R = 1e6;
  for (int levels = 0; levels <= 5; ++levels)
    CHECK(cube_fraction(lo, 1.0, {0.5 - R, 0.5, 0.5}, R, levels) == (levels == 0 ? 0.0 : 0.5));
}

TEST_CASE("a sphere's summed fractions converge to its volume as the octree refines", "[immersed][psm]") {
  // Radius 4 cells, centre off the grid's symmetry points; levels 1..5.
  const double r = 4.0;
  const V c{10.3, 9.71, 10.17};
  const double exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  double err[6] = {};
  for (int levels = 1; levels <= 5; ++levels) {
    double sum = 0.0;
    for (int k = 0; k < 20; ++k)
      for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 20; ++i)
          sum += cube_fraction({double(i), double(j), double(k)}, 1.0, c, r, levels);
    err[levels] = std::abs(sum / exact - 1.0);
    INFO("levels " << levels << ": relative volume error " << err[levels]);
    // Measured 5.0e-3, 9.2e-4, 1.3e-4, 4.2e-5, 3.3e-5 for this centre: about
    // twice that (the leaves' centre rule has no strict rate, only a shrinking band).
    const double bound[6] = {0, 1e-2, 2e-3, 3e-4, 1e-4, 1e-4};
    CHECK(err[levels] < bound[levels]);
  }
  // The default (3 levels) is ten times better than one level.
  CHECK(err[3] < 0.1 * err[1]);
}

namespace {

using Cells = std::vector<std::pair<coflow::coupler::Index3, double>>;

// Cells as a map for comparison (absent = 0).
std::map<coflow::coupler::Index3, double> as_map(const Cells& cells) {
  std::map<coflow::coupler::Index3, double> m;
  for (const auto& [c, f] : cells) m[c] = f;
  return m;
}

double max_difference(const Cells& a, const Cells& b) {
  auto ma = as_map(a), mb = as_map(b);
  double worst = 0.0;
  for (const auto& [c, f] : ma)
    worst = coflow::test::worst_of(worst, std::abs(f - (mb.count(c) ? mb[c] : 0.0)));
  for (const auto& [c, f] : mb)
    worst = coflow::test::worst_of(worst, std::abs(f - (ma.count(c) ? ma[c] : 0.0)));
  return std::isfinite(worst) ? worst : 1e300;
}

// Centre number s of a set spread over a cell near (20, 21, 19.5) cells
// from `lower`.
V spread_centre(const V& lower, double h, int s) {
  return {lower[0] + (20.0 + std::fmod(0.0831 * s, 1.0)) * h, lower[1] + (21.0 + std::fmod(0.377 * s, 1.0)) * h,
          lower[2] + (19.5 + std::fmod(0.6123 * s, 1.0)) * h};
}

double sum(const Cells& a) {
  double s = 0.0;
  for (const auto& [c, f] : a) s += f;
  return s;
}

}  // namespace

TEST_CASE("fractions kept on a lattice of centre offsets stay within the octree's own error",
          "[immersed][psm]") {
  // Cells of 0.5 mm from an origin off zero; radius 4 and 8 cells; 12 centres
  // spread over the cell. The octree's own error per cell: 3 levels against 6
  // (the 'truth'), at the same exact centre.
  using coflow::immersed::SphereFractions;
  const double h = 5e-4;
  const V lower{-0.01, 0.002, 0.0};
  for (double radius_cells : {4.0, 8.0}) {
    const std::vector<double> radii{radius_cells * h};
    SphereFractions exact(h, lower, 3, 0, {}), truth(h, lower, 6, 0, {}), kept(h, lower, 3, 8, radii);
    double worst_kept = 0.0, worst_octree = 0.0, worst_apart = 0.0, worst_volume = 0.0;
    for (int s = 0; s < 12; ++s) {
      const V c = spread_centre(lower, h, s);
      Cells e, t, k;
      exact.cover(c, radius_cells * h, e);
      truth.cover(c, radius_cells * h, t);
      kept.cover(c, radius_cells * h, k);
      const double volume = 4.0 / 3.0 * std::numbers::pi * std::pow(radius_cells, 3);
      worst_volume = coflow::test::worst_of(worst_volume,
                                            std::abs(sum(k) / volume - 1.0));  // the interpolation keeps it
      worst_kept = coflow::test::worst_of(worst_kept, max_difference(k, t));
      worst_octree = coflow::test::worst_of(worst_octree, max_difference(e, t));
      worst_apart = coflow::test::worst_of(worst_apart, max_difference(k, e));
    }
    INFO("radius " << radius_cells << " cells, largest error of a cell's fraction against 6 levels: kept "
                   << worst_kept << ", exact centre " << worst_octree << "; kept vs exact centre "
                   << worst_apart);
    INFO("relative volume error of the kept fractions " << worst_volume);
    CHECK(worst_kept < worst_octree);
    CHECK(worst_apart < 0.1);
    CHECK(worst_volume < 2e-14);  // 1.3e-15 and 2.3e-15 measured: round-off of the sums
  }
}

TEST_CASE("kept fractions move with the sphere by whole cells, and equal the exact ones on the lattice",
          "[immersed][psm]") {
  using coflow::immersed::SphereFractions;
  const double h = 1.0;  // powers of two: centres on the lattice are exact
  SphereFractions kept(h, {0, 0, 0}, 3, 8, {3.5}), exact(h, {0, 0, 0}, 3, 0, {});
  Cells a, b, e;
  kept.cover({10.25, 10.625, 10.5}, 3.5, a);
  exact.cover({10.25, 10.625, 10.5}, 3.5, e);
  CHECK(max_difference(a, e) <= 0.0);
  kept.cover({10.5625, 10.8125, 10.0625}, 3.5, a);
  kept.cover({12.5625, 7.8125, 11.0625}, 3.5, b);  // + (2, -3, 1) cells
  for (auto& [c, f] : b) c = {c[0] - 2, c[1] + 3, c[2] - 1};
  CHECK(max_difference(a, b) <= 0.0);
  CHECK(kept.stencils_computed() == 9);  // one for the lattice centre, eight around the other
  // A radius not among the kept ones (a size distribution) takes the exact centre.
  kept.cover({10.5625, 10.8125, 10.0625}, 3.25, a);
  exact.cover({10.5625, 10.8125, 10.0625}, 3.25, e);
  CHECK(max_difference(a, e) <= 0.0);
  CHECK(kept.stencils_computed() == 9);
}

TEST_CASE("kept stencils dropped when their memory is full give the same fractions", "[immersed][psm]") {
  using coflow::immersed::SphereFractions;
  // Two kept radii; `tight` drops every stencil it keeps as soon as it holds more than one byte, so its
  // lookup tables are emptied again and again between the eight corners of one sphere.
  SphereFractions roomy(1.0, {0, 0, 0}, 3, 8, {2.0, 3.5}), tight(1.0, {0, 0, 0}, 3, 8, {2.0, 3.5}, 1);
  Cells a, b;
  double worst = 0.0;
  std::size_t cells = 0;
  for (int n = 0; n < 40; ++n) {
    const double r = n % 2 ? 2.0 : 3.5;
    const V c{10.0 + 0.137 * (n % 10), 11.0 + 0.291 * (n % 10),
              9.0 + 0.053 * (n % 10)};  // each centre 4 times
    roomy.cover(c, r, a);
    tight.cover(c, r, b);
    REQUIRE(a.size() == b.size());
    worst = coflow::test::worst_of(worst, max_difference(a, b));
    cells += a.size();
  }
  CHECK(worst <= 0.0);
  CHECK(cells > 40 * 30);
  CHECK(tight.stencils_computed() >
        2 * roomy.stencils_computed());  // the tight one recomputes what it dropped
}

TEST_CASE("a full memory drops the kept stencils but keeps their symmetry classes' octree stencils",
          "[immersed][psm]") {
  using coflow::immersed::SphereFractions;
  // r = 3.5 cells: stencils of 11^3 doubles (10.6 kB). The 35 classes (373 kB)
  // fit in half of 1 MiB; the 729 kept stencils (7.8 MB) do not, so `small`
  // drops them again and again as the sphere visits every offset twice.
  SphereFractions roomy(1.0, {0, 0, 0}, 3, 8, {3.5}),
      small(1.0, {0, 0, 0}, 3, 8, {3.5}, std::size_t{1} << 20);
  Cells a, b;
  double worst = 0.0;
  for (int pass = 0; pass < 2; ++pass)
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j)
        for (int k = 0; k <= 8; ++k) {
          const V c{10 + i / 8.0, 20 + j / 8.0, 30 + k / 8.0};
          roomy.cover(c, 3.5, a);
          small.cover(c, 3.5, b);
          REQUIRE(a.size() == b.size());
          worst = coflow::test::worst_of(worst, max_difference(a, b));
        }
  CHECK(worst <= 0.0);
  CHECK(small.stencils_computed() > roomy.stencils_computed());  // it did drop kept stencils
  CHECK(roomy.octree_stencils() == 35);
  CHECK(small.octree_stencils() == 35);  // but no class twice (383 when the classes went with them)
}

TEST_CASE("kept stencils taken from their symmetry class equal the octree's at every offset of the lattice",
          "[immersed][psm]") {
  using coflow::immersed::SphereFractions;
  // Offsets a/8 and (8 - a)/8 are mirror images and the axes may be swapped:
  // 35 classes hold the 9^3 = 729 offsets, and the fractions read back through
  // the mirror and the permutation are the octree's own, bit for bit.
  for (const double radius : {2.3, 3.5}) {
    SphereFractions kept(1.0, {0, 0, 0}, 3, 8, {radius}), exact(1.0, {0, 0, 0}, 3, 0, {});
    Cells a, e;
    double worst = 0.0;
    std::size_t compared = 0;
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j)
        for (int k = 0; k <= 8; ++k) {
          const V c{10 + i / 8.0, 20 + j / 8.0, 30 + k / 8.0};  // on the lattice: one kept stencil, weight 1
          kept.cover(c, radius, a);
          exact.cover(c, radius, e);
          REQUIRE(a.size() == e.size());
          worst = coflow::test::worst_of(worst, max_difference(a, e));
          compared += a.size();
        }
    INFO("radius " << radius << ": " << compared << " cells compared");
    CHECK(worst <= 0.0);
    // The offsets 8/8 along an axis are the next cell's 0/8: 512 kept stencils.
    CHECK(kept.stencils_computed() == 512);
    // Folded offsets 0..4 per axis, sorted: C(5 + 2, 3) = 35 octree stencils.
    CHECK(kept.octree_stencils() == 35);
  }
}

TEST_CASE("rounded blend weights move a cell's fraction by less than the centre's shift, and keep the volume",
          "[immersed][psm]") {
  // Rounding the trilinear weights to multiples of 1/M moves the centre the
  // fractions are taken at by at most h / (2 N M) per axis. A sphere moved by
  // d cells changes a cell's fraction by at most about d per axis (the cut
  // surface sweeps at most a face of the cell), so by 3 / (2 N M) in all:
  // 1.5e-3 at N = 8, M = 128, the bound below (from the geometry, not from a
  // run). How close either stays to the octree's truth is the test above's.
  using coflow::immersed::SphereFractions;
  const double h = 5e-4;
  const V lower{-0.01, 0.002, 0.0};
  const int N = 8, M = 128;
  for (double radius_cells : {2.0, 4.0, 8.0}) {
    const std::vector<double> radii{radius_cells * h};
    SphereFractions kept(h, lower, 3, N, radii), rounded(h, lower, 3, N, radii, std::size_t{256} << 20, M);
    double worst = 0.0, worst_volume = 0.0;
    for (int s = 0; s < 40; ++s) {
      const V c = spread_centre(lower, h, s);
      Cells k, r;
      kept.cover(c, radius_cells * h, k);
      rounded.cover(c, radius_cells * h, r);
      const double volume = 4.0 / 3.0 * std::numbers::pi * std::pow(radius_cells, 3);
      worst_volume = coflow::test::worst_of(worst_volume, std::abs(sum(r) / volume - 1.0));
      worst = coflow::test::worst_of(worst, max_difference(k, r));
    }
    INFO("radius " << radius_cells << " cells: rounded vs unrounded " << worst << "; volume "
                   << worst_volume);
    CHECK(worst <= 3.0 / (2.0 * N * M));
    CHECK(worst > 0.0);           // the rounding did act
    CHECK(worst_volume < 2e-14);  // the weights still add up to 1: round-off of the sums
  }
}

TEST_CASE("a sphere keeps its cells while its rounded centre stays, and they equal a fresh cover's",
          "[immersed][psm]") {
  // Compared as sequences (==): the same cells in the same order, the same
  // bits (psm adds them up in this order).
  using coflow::immersed::SphereFractions;
  const double h = 1.0, r = 2.5;
  SphereFractions memo(h, {0, 0, 0}, 3, 8, {r}, std::size_t{256} << 20, 128),
      fresh(h, {0, 0, 0}, 3, 8, {r}, std::size_t{256} << 20, 128);
  Cells f;
  const V c{10.3, 11.7, 9.1};
  CHECK(memo.cover_of(7, c, r) == (fresh.cover(c, r, f), f));
  memo.forget_unasked();
  // Moved by 1e-6 cells: the rounded weights (steps of 1/1024 cell) are the same.
  const V near{c[0] + 1e-6, c[1] - 1e-6, c[2] + 1e-6};
  const Cells b = memo.cover_of(7, near, r);  // a copy: the next call for sphere 7 replaces its list
  CHECK(memo.lists_reused() == 1);
  CHECK(b == (fresh.cover(near, r, f), f));
  memo.forget_unasked();
  // Moved by a step: computed again.
  const V moved{c[0] + 1.0 / 512, c[1], c[2]};
  CHECK(memo.cover_of(7, moved, r) == (fresh.cover(moved, r, f), f));
  CHECK(memo.lists_reused() == 1);
  CHECK(max_difference(f, b) > 0.0);
  memo.forget_unasked();
  // Moved by a whole cell (the same offset in its cell), or given another
  // radius under the same id: computed again.
  const V next_cell{moved[0] + 1.0, moved[1], moved[2]};
  CHECK(memo.cover_of(7, next_cell, r) == (fresh.cover(next_cell, r, f), f));
  memo.forget_unasked();
  CHECK(memo.cover_of(7, next_cell, 2.25) == (fresh.cover(next_cell, 2.25, f), f));
  memo.forget_unasked();
  CHECK(memo.lists_reused() == 1);
  // Another sphere at the same place has its own list; a sphere not asked for
  // in a round is forgotten.
  memo.cover_of(8, moved, r);
  memo.forget_unasked();
  memo.cover_of(8, moved, r);
  memo.forget_unasked();
  memo.cover_of(7, next_cell, 2.25);  // forgotten in the round before: computed again
  CHECK(memo.lists_reused() == 2);
  CHECK(memo.lists_asked() == 8);
  // A radius that keeps no stencils (exact centre) keeps its cells only while
  // the centre is exactly where it was.
  memo.forget_unasked();
  memo.cover_of(9, c, 2.25);
  memo.forget_unasked();
  memo.cover_of(9, c, 2.25);
  memo.forget_unasked();
  CHECK(memo.cover_of(9, near, 2.25) == (fresh.cover(near, 2.25, f), f));
  CHECK(memo.lists_reused() == 3);
}

TEST_CASE("when the kept lists fill their memory, new spheres are covered without being kept",
          "[immersed][psm]") {
  using coflow::immersed::SphereFractions;
  const double r = 2.5;
  // 1 byte: the first list is kept (the budget is checked before), no other.
  SphereFractions tight(1.0, {0, 0, 0}, 3, 8, {r}, 1, 128),
      fresh(1.0, {0, 0, 0}, 3, 8, {r}, std::size_t{256} << 20, 128);
  Cells f;
  const V a{10.3, 11.7, 9.1}, b{20.6, 11.2, 9.9};
  for (int round = 0; round < 3; ++round) {
    CHECK(tight.cover_of(1, a, r) == (fresh.cover(a, r, f), f));
    CHECK(tight.cover_of(2, b, r) == (fresh.cover(b, r, f), f));
    tight.forget_unasked();
  }
  CHECK(tight.lists_reused() == 2);  // sphere 1 in rounds 2 and 3; sphere 2 never kept
  CHECK(tight.lists_asked() == 6);
}
