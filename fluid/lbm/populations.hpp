// One set of populations of a block: the post-collision populations of the
// last step (f) and of the step being computed (next), Layout::stride apart,
// with the halo exchange that fills f's ghosts. The single-phase solver holds
// one set; a two-phase (colour-gradient) solver holds two, red and blue, over
// the same Layout, boundaries and kernels.
#pragma once

#include <utility>

#include "coflow/memory.hpp"
#include "fluid/lbm/halo.hpp"

namespace coflow::fluid::lbm {

template <class L>
struct Populations {
  StridedArrays<double> f, next;
  HaloExchange<L> halo;

  // Q arrays of `cells` values, `stride` apart; throws std::bad_alloc where
  // the address space is refused (f is then released again).
  void allocate(long stride, long cells) {
    f = {};
    next = {};
    f = StridedArrays<double>(L::Q, stride, cells);
    next = StridedArrays<double>(L::Q, stride, cells);
  }
  void swap() { std::swap(f, next); }
};

}  // namespace coflow::fluid::lbm
