// The rank split that balances a coupled run (coflow/rank_split.hpp): exact
// optima of the two wall-time models, worked by hand.
#include <catch2/catch.hpp>

#include "coflow/rank_split.hpp"

using coflow::coupler::balance_ranks;
using coflow::coupler::ComponentLoad;
using coflow::coupler::rank_advice;

TEST_CASE("overlapped components get ranks in proportion to their work", "[coupler][ranks]") {
  // Work (compute x ranks): fluid 6 x 1 = 6, immersed 1 x 2 = 2, particles 1 x 1 = 1 (4 ranks).
  // Largest work / ranks: (1, 2, 1) -> 6; (2, 1, 1) -> 3; the best of all splits.
  const std::vector<ComponentLoad> loads{{"fluid", 1, 6.0}, {"immersed", 2, 1.0}, {"particles", 1, 1.0}};
  const auto r = balance_ranks(loads, true);
  CHECK(r.ranks == std::vector<int>{2, 1, 1});
  CHECK(r.wall_now == 6.0);
  CHECK(r.wall_balanced == 3.0);
  CHECK(rank_advice(loads, true).rfind("fluid 2, immersed 1, particles 1 would balance this run (about 50 %", 0) == 0);
  // Two components tie for the longest: work 1, 6, 6 on 5 ranks; (1, 2, 2)
  // halves the largest (6 -> 3), which no single extra rank shows.
  const auto tie = balance_ranks({{"fluid", 3, 1.0 / 3.0}, {"immersed", 1, 6.0}, {"particles", 1, 6.0}}, true);
  CHECK(tie.ranks == std::vector<int>{1, 2, 2});
  CHECK(tie.wall_balanced == 3.0);
}

TEST_CASE("components that take turns get ranks by the square root of their work", "[coupler][ranks]") {
  // Work 16, 4, 1 on 7 ranks (sqrt: 4 : 2 : 1). Sum of work / ranks:
  // (4, 2, 1) -> 4 + 2 + 1 = 7; e.g. (5, 1, 1) -> 3.2 + 4 + 1 = 8.2, (3, 3, 1) -> 7.67.
  const std::vector<ComponentLoad> loads{{"fluid", 1, 16.0}, {"immersed", 5, 0.8}, {"particles", 1, 1.0}};
  const auto r = balance_ranks(loads, false);
  CHECK(r.ranks == std::vector<int>{4, 2, 1});
  CHECK(r.wall_now == Approx(16.0 + 0.8 + 1.0));
  CHECK(r.wall_balanced == Approx(7.0));
  // A run already balanced gets no advice.
  CHECK(rank_advice({{"fluid", 4, 4.0}, {"immersed", 2, 2.0}, {"particles", 1, 1.0}}, false).empty());
}
