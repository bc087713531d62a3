// One set of populations of a block: the post-collision populations of the
// last step (f) and of the step being computed (next), W Layout::stride apart,
// with the halo exchange that fills f's ghosts. W values per cell and
// population: 1 in the single-phase solver; 2 in the two-phase
// (colour-gradient) one, whose red and blue populations q of a cell sit side
// by side, so that its kernels pull and store 19 streams, not 38.
#pragma once

#include <utility>

#include "coflow/memory.hpp"
#include "fluid/lbm/halo.hpp"

namespace coflow::fluid::lbm {

template <class L, int W = 1>
struct Populations {
  StridedArrays<double> f, next;
  HaloExchange<L, W> halo;

  // Q arrays of `cells` cells (W values each), W `stride` values apart;
  // throws std::bad_alloc where the address space is refused (f is then
  // released again).
  void allocate(long stride, long cells) {
    f = {};
    next = {};
    f = StridedArrays<double>(L::Q, W * stride, W * cells);
    next = StridedArrays<double>(L::Q, W * stride, W * cells);
  }
  void swap() { std::swap(f, next); }
};

}  // namespace coflow::fluid::lbm
