// The impulse the particles give each wall, kept by every particle variant for
// series/walls.csv (particles/wall_loads.*): 3 values per wall, the six faces
// of the domain (x-, x+, y-, y+, z-, z+) and then the mesh walls in the order
// of particles.walls. A contact force F on a particle over a step h gives the
// wall -F h; a hard-sphere collision that changes a particle's velocity by dv
// gives it -m dv. The sums are exact (coupler::ExactSums): they do not depend
// on the order of the contacts or on which rank holds a particle.
#pragma once

#include <cstddef>
#include <utility>

#include "coflow/reproducible_sum.hpp"

namespace coflow::particles {

class WallImpulse {
 public:
  void reset(std::size_t meshes) { sum_ = coupler::ExactSums(3 * (6 + meshes)); }
  // Face f (0-5), or mesh m as slot 6 + m.
  template <class V>
  void add(std::size_t slot, const V& impulse) {
    for (int q = 0; q < 3; ++q) sum_.add(3 * slot + q, impulse[q]);
  }
  // This rank's impulses since the last call; zeroes them.
  coupler::ExactSums take() {
    coupler::ExactSums out(sum_.size());
    std::swap(out, sum_);
    return out;
  }

 private:
  coupler::ExactSums sum_;
};

}  // namespace coflow::particles
