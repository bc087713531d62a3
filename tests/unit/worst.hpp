// The worst of a set of errors, in a way that a NaN cannot hide from.
#pragma once

#include <algorithm>
#include <cmath>

namespace coflow::test {

// The larger of a worst value so far and a new one; a NaN makes it infinite
// (std::max(so_far, NaN) returns so_far), so that a bound check sees it.
inline double worst_of(double so_far, double value) {
  return std::isnan(value) ? HUGE_VAL : std::max(so_far, value);
}

}  // namespace coflow::test
