#include "coflow/rank_split.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace coflow::coupler {

namespace {

double model_wall(const std::vector<double>& work, const std::vector<int>& ranks, bool overlapped) {
  double sum = 0.0, most = 0.0;
  for (std::size_t c = 0; c < work.size(); ++c) {
    sum += work[c] / ranks[c];
    most = std::max(most, work[c] / ranks[c]);
  }
  return overlapped ? most : sum;
}

std::string listed(const std::vector<ComponentLoad>& loads, const std::vector<int>& ranks) {
  std::string s;
  for (std::size_t c = 0; c < loads.size(); ++c) s += fmt::format("{}{} {}", c ? ", " : "", loads[c].name, ranks[c]);
  return s;
}

}  // namespace

RankSplit balance_ranks(const std::vector<ComponentLoad>& loads, bool overlapped) {
  std::vector<double> work;
  std::vector<int> now;
  int total = 0;
  for (const auto& l : loads) {
    work.push_back(std::max(0.0, l.compute_s) * l.ranks);
    now.push_back(l.ranks);
    total += l.ranks;
  }
  RankSplit r;
  r.ranks.assign(loads.size(), 1);
  for (int given = static_cast<int>(loads.size()); given < total; ++given) {
    // Overlapped: the rank goes to the component that takes longest (ties
    // would hide the gain from a test of the maximum). Taking turns: where it
    // shortens the sum the most.
    std::size_t best = 0;
    double best_value = overlapped ? -1.0 : 1e300;
    for (std::size_t c = 0; c < loads.size(); ++c) {
      double v = work[c] / r.ranks[c];
      if (!overlapped) {
        ++r.ranks[c];
        v = model_wall(work, r.ranks, false);
        --r.ranks[c];
      }
      if (overlapped ? v > best_value : v < best_value) best_value = v, best = c;
    }
    ++r.ranks[best];
  }
  r.wall_now = model_wall(work, now, overlapped);
  r.wall_balanced = model_wall(work, r.ranks, overlapped);
  // Keep the run's own split where the model cannot tell them apart.
  if (r.wall_balanced >= r.wall_now) r.ranks = now, r.wall_balanced = r.wall_now;
  return r;
}

std::string rank_advice(const std::vector<ComponentLoad>& loads, bool overlapped) {
  if (loads.size() < 2) return "";
  const RankSplit r = balance_ranks(loads, overlapped);
  if (!(r.wall_now > 0.0) || r.wall_balanced > 0.9 * r.wall_now) return "";
  std::vector<int> now;
  for (const auto& l : loads) now.push_back(l.ranks);
  return fmt::format("{} would balance this run (about {:.0f} % less wall time than {}, from the components' "
                     "compute times{})",
                     listed(loads, r.ranks), 100.0 * (1.0 - r.wall_balanced / r.wall_now), listed(loads, now),
                     overlapped ? "" : "; they take turns in serial-explicit");
}

}  // namespace coflow::coupler
