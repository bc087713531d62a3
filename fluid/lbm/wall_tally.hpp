// The momentum the walls and interior solids take from the fluid (Ladd's
// momentum exchange, series/fluid_walls.csv), kept per fluid cell and per wall
// or solid it borders, so that the window's sums do not depend on the rank
// count: each cell's links are taken on the rank that owns it, in a fixed
// order, step after step, and the cells' sums are added exactly
// (coupler::ExactSums) at the window's end. A plain running sum per face, as
// before 2026-12-05, added the cells in each rank's loop order, and 1 rank
// and N ranks differed in the last bits.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <vector>

#include "coflow/reproducible_sum.hpp"

namespace coflow::fluid::lbm {

class WallTally {
 public:
  // `cells` owned cells; slots_of(c, out) lists cell c's slots (face 0-5 for
  // the box's walls, 6 + n for interior solid n), each once.
  void build(long cells, int slots, const std::function<void(long, std::vector<int>&)>& slots_of) {
    slots_ = slots;
    first_.assign(static_cast<std::size_t>(cells) + 1, 0);
    slot_.clear();
    std::vector<int> list;
    for (long c = 0; c < cells; ++c) {
      list.clear();
      slots_of(c, list);
      slot_.insert(slot_.end(), list.begin(), list.end());
      first_[static_cast<std::size_t>(c) + 1] = static_cast<std::int64_t>(slot_.size());
    }
    sum_.assign(3 * slot_.size(), 0.0);
  }
  // The three sums of owned cell c for `slot` (which build listed for it).
  double* at(long c, int slot) {
    for (auto n = first_[static_cast<std::size_t>(c)]; n < first_[static_cast<std::size_t>(c) + 1]; ++n)
      if (slot_[static_cast<std::size_t>(n)] == slot) return &sum_[3 * static_cast<std::size_t>(n)];
    missing();
  }
  // Every slot's sums times `unit`, as exact sums (3 per slot), and zeroed.
  coupler::ExactSums take(double unit) {
    coupler::ExactSums out(3 * static_cast<std::size_t>(slots_));
    for (std::size_t n = 0; n < slot_.size(); ++n)
      for (int d = 0; d < 3; ++d) out.add(3 * static_cast<std::size_t>(slot_[n]) + d, unit * sum_[3 * n + d]);
    std::fill(sum_.begin(), sum_.end(), 0.0);
    return out;
  }

 private:
  [[noreturn, gnu::cold, gnu::noinline]] static void missing() {
    throw std::logic_error("lbm: a wall or solid link that the wall tally has no slot for");
  }
  int slots_ = 0;
  std::vector<std::int64_t> first_;  // cell c's slots: slot_[first_[c] .. first_[c + 1])
  std::vector<int> slot_;
  std::vector<double> sum_;  // 3 per listed (cell, slot)
};

}  // namespace coflow::fluid::lbm
