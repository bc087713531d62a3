#include <catch2/catch.hpp>

#include <set>

#include "coflow/decomposition.hpp"

using namespace coflow::coupler;

TEST_CASE("blocks tile the domain exactly once", "[decomposition]") {
  for (int ranks = 1; ranks <= 12; ++ranks) {
    const Decomposition d({17, 9, 5}, ranks);
    long volume = 0;
    for (int r = 0; r < ranks; ++r) volume += d.block(r).volume();
    CHECK(volume == 17 * 9 * 5);
    for (long k = 0; k < 5; ++k)
      for (long j = 0; j < 9; ++j)
        for (long i = 0; i < 17; ++i) {
          const int o = d.owner({i, j, k});
          REQUIRE(o >= 0);
          CHECK(d.block(o).contains({i, j, k}));
        }
  }
}

TEST_CASE("balanced dims cut the least area", "[decomposition]") {
  CHECK(choose_dims({64, 64, 64}, 8) == std::array<int, 3>{2, 2, 2});
  CHECK(choose_dims({128, 16, 16}, 4) == std::array<int, 3>{4, 1, 1});
  CHECK(choose_dims({32, 32, 1}, 4) == std::array<int, 3>{2, 2, 1});  // 2D keeps z whole
  CHECK_THROWS(choose_dims({2, 1, 1}, 3));
}

TEST_CASE("explicit dims are honoured and checked", "[decomposition]") {
  const Decomposition d({8, 8, 8}, 4, {1, 1, 4});
  CHECK(d.block(3).lo[2] == 6);
  CHECK_THROWS(Decomposition({8, 8, 8}, 4, {1, 2, 3}));
}

TEST_CASE("periodic wrap and image shifts", "[decomposition]") {
  const Decomposition d({10, 4, 1}, 2, {0, 0, 0}, {true, false, false});
  CHECK(d.wrap({-1, 2, 0}) == Index3{9, 2, 0});
  CHECK(d.wrap({10, 2, 0}) == Index3{0, 2, 0});
  CHECK(d.owner({-1, 0, 0}) == d.owner({9, 0, 0}));
  CHECK(d.owner({0, -1, 0}) == -1);  // y is not periodic
  CHECK(d.image_shifts().size() == 3);
  CHECK(d.ghost(2) == Index3{2, 2, 0});
  const Box c = d.clip(Box{{-2, -2, 0}, {3, 3, 1}});
  CHECK(c.lo == Index3{-2, 0, 0});  // periodic x keeps its ghost cells
}
