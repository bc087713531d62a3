// Which cell of the fluid grid a particle is in, along one axis: the one rule
// the particle models share (particles/store/domain.hpp's owners, dpm's eq.
// 4.15 cells).
#pragma once

#include <cmath>

namespace coflow::particles::store {

// The cell along one axis of a grid of `cells` over [lower, upper) that
// holds x, clamped into the grid: the one rule for which rank owns a particle
// (Domain::owner_of) and which fluid cell it counts in (dpm's tau_c of eq.
// 4.15), so that a cell's particles are always on one rank.
// (Clamped as a double, so that no position, NaN included, casts out of range.)
inline long grid_cell(double x, double lower, double upper, long cells) {
  const double f = std::floor((x - lower) / (upper - lower) * static_cast<double>(cells));
  return f >= static_cast<double>(cells - 1) ? cells - 1 : f >= 0.0 ? static_cast<long>(f) : 0L;
}

}  // namespace coflow::particles::store
