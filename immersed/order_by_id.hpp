// The records a window brings (particles or their impulses), in the order of
// their particle ids.
#pragma once

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace coflow::immersed {

// order = the indices 0 .. n-1 sorted by id(index). Records arrive in an
// order that follows particles.ranks and migration; a cell's sums taken over
// them in this order are the same for any number of immersed and particle
// ranks. Ids are unique among one rank's records.
template <class Id>
void order_by_id(std::size_t n, std::vector<std::size_t>& order, Id&& id) {
  order.resize(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&id](std::size_t a, std::size_t b) { return id(a) < id(b); });
}

}  // namespace coflow::immersed
