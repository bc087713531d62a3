#include "coflow/decomposition.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace coflow::coupler {

Box intersect(const Box& a, const Box& b) {
  Box r;
  for (int d = 0; d < 3; ++d) {
    r.lo[d] = std::max(a.lo[d], b.lo[d]);
    r.hi[d] = std::max(r.lo[d], std::min(a.hi[d], b.hi[d]));
  }
  return r;
}

std::array<int, 3> choose_dims(const Index3& cells, int ranks) {
  std::array<int, 3> best{ranks, 1, 1};
  double best_cost = std::numeric_limits<double>::max();
  for (int a = 1; a <= ranks; ++a) {
    if (ranks % a) continue;
    for (int b = 1; b <= ranks / a; ++b) {
      if ((ranks / a) % b) continue;
      const int c = ranks / a / b;
      const std::array<int, 3> d{a, b, c};
      bool fits = true;
      for (int k = 0; k < 3; ++k) fits = fits && d[k] <= cells[k];
      if (!fits) continue;
      // Cut area: each extra block along an axis adds one plane of the others.
      const double cost = (a - 1.0) * cells[1] * cells[2] + (b - 1.0) * cells[0] * cells[2] +
                          (c - 1.0) * cells[0] * cells[1];
      if (cost < best_cost - 1e-9) {
        best_cost = cost;
        best = d;
      }
    }
  }
  if (best_cost == std::numeric_limits<double>::max())
    throw std::invalid_argument(fmt::format("cannot split {}x{}x{} cells into {} blocks", cells[0],
                                            cells[1], cells[2], ranks));
  return best;
}

Decomposition::Decomposition(const Index3& cells, int ranks, std::array<int, 3> dims,
                             std::array<bool, 3> periodic)
    : cells_(cells), ranks_(ranks), periodic_(periodic) {
  if (ranks < 1) throw std::invalid_argument("a decomposition needs at least one rank");
  dims_ = (dims[0] * dims[1] * dims[2] == 0) ? choose_dims(cells, ranks) : dims;
  if (dims_[0] * dims_[1] * dims_[2] != ranks)
    throw std::invalid_argument(fmt::format("decomposition {}x{}x{} does not match {} ranks",
                                            dims_[0], dims_[1], dims_[2], ranks));
  for (int d = 0; d < 3; ++d) {
    if (dims_[d] > cells[d])
      throw std::invalid_argument(
          fmt::format("{} blocks along axis {} but only {} cells", dims_[d], "xyz"[d], cells[d]));
    cuts_[d].resize(dims_[d] + 1);
    const long base = cells[d] / dims_[d], extra = cells[d] % dims_[d];
    cuts_[d][0] = 0;
    for (int i = 0; i < dims_[d]; ++i) cuts_[d][i + 1] = cuts_[d][i] + base + (i < extra ? 1 : 0);
  }
  blocks_.resize(ranks);
  for (int r = 0; r < ranks; ++r) {
    const int i = r % dims_[0], j = (r / dims_[0]) % dims_[1], k = r / (dims_[0] * dims_[1]);
    blocks_[r] = Box{{cuts_[0][i], cuts_[1][j], cuts_[2][k]},
                     {cuts_[0][i + 1], cuts_[1][j + 1], cuts_[2][k + 1]}};
  }
}

Index3 Decomposition::wrap(Index3 c) const {
  for (int d = 0; d < 3; ++d)
    if (periodic_[d]) c[d] = ((c[d] % cells_[d]) + cells_[d]) % cells_[d];
  return c;
}

int Decomposition::owner(Index3 c) const {
  c = wrap(c);
  std::array<int, 3> b{};
  for (int d = 0; d < 3; ++d) {
    if (c[d] < 0 || c[d] >= cells_[d]) return -1;
    b[d] = static_cast<int>(std::upper_bound(cuts_[d].begin(), cuts_[d].end(), c[d]) - cuts_[d].begin()) - 1;
  }
  return b[0] + dims_[0] * (b[1] + dims_[1] * b[2]);
}

Index3 Decomposition::ghost(int width) const {
  Index3 g{};
  for (int d = 0; d < 3; ++d) g[d] = cells_[d] > 1 ? width : 0;
  return g;
}

std::vector<Index3> Decomposition::image_shifts() const {
  std::vector<Index3> s;
  for (int k = -1; k <= 1; ++k)
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i) {
        const std::array<int, 3> m{i, j, k};
        bool ok = true;
        for (int d = 0; d < 3; ++d) ok = ok && (m[d] == 0 || periodic_[d]);
        if (ok) s.push_back({i * cells_[0], j * cells_[1], k * cells_[2]});
      }
  return s;
}

Box Decomposition::clip(const Box& b) const {
  Box r = b;
  for (int d = 0; d < 3; ++d)
    if (!periodic_[d]) {
      r.lo[d] = std::max(r.lo[d], 0L);
      r.hi[d] = std::max(r.lo[d], std::min(r.hi[d], cells_[d]));
    }
  return r;
}

}  // namespace coflow::coupler
