// The split of a run's ranks among its components that balances it, from each
// component's compute time in a finished run (summary.json): the launcher
// prints it after a run, `coflow validate` from the last run's summary.
//
// A component's work is its compute time per rank x its ranks (perfect
// scaling assumed). Serial-explicit components take turns, so the wall time
// is about the sum of work / ranks: the best split gives each rank count in
// proportion to the square root of the work. Parallel-explicit components
// overlap, so the wall time is about the largest work / ranks: the best split
// is in proportion to the work. Whole ranks, at least one each, the total
// kept, given one at a time: for the sum to the component whose extra rank
// shortens it most, for the maximum to the component that takes longest
// (both greedy rules are optimal for their objective).
#pragma once

#include <string>
#include <vector>

namespace coflow::coupler {

struct ComponentLoad {
  std::string name;
  int ranks = 1;
  double compute_s = 0.0;  // per rank
};

struct RankSplit {
  std::vector<int> ranks;       // in the order of the loads
  double wall_now = 0.0;        // the model's wall time of the run as it was
  double wall_balanced = 0.0;   // and with the split
};

RankSplit balance_ranks(const std::vector<ComponentLoad>& loads, bool overlapped);

// "fluid 2, immersed 1, particles 1 would balance this run (about 25 % less
// wall time than fluid 1, ...)", or "" when the split is the run's own or
// saves less than 10 %.
std::string rank_advice(const std::vector<ComponentLoad>& loads, bool overlapped);

}  // namespace coflow::coupler
