// Cartesian block decomposition of the global cell grid. Every component can
// compute every other component's decomposition from the configuration alone,
// which is what lets the coupler build its M x N maps without communication.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace coflow::coupler {

using Index3 = std::array<long, 3>;

// Half-open box of cells [lo, hi).
struct Box {
  Index3 lo{0, 0, 0};
  Index3 hi{0, 0, 0};
  long extent(int d) const { return hi[d] - lo[d]; }
  long volume() const {
    long v = 1;
    for (int d = 0; d < 3; ++d) v *= (hi[d] > lo[d] ? hi[d] - lo[d] : 0);
    return v;
  }
  bool empty() const { return volume() == 0; }
  bool contains(const Index3& c) const {
    for (int d = 0; d < 3; ++d)
      if (c[d] < lo[d] || c[d] >= hi[d]) return false;
    return true;
  }
  Box grown(const Index3& g) const {
    Box b = *this;
    for (int d = 0; d < 3; ++d) {
      b.lo[d] -= g[d];
      b.hi[d] += g[d];
    }
    return b;
  }
  Box shifted(const Index3& s) const {
    Box b = *this;
    for (int d = 0; d < 3; ++d) {
      b.lo[d] += s[d];
      b.hi[d] += s[d];
    }
    return b;
  }
  friend bool operator==(const Box&, const Box&) = default;
};

Box intersect(const Box& a, const Box& b);

class Decomposition {
 public:
  Decomposition() = default;
  // dims: blocks per axis; all zero means choose (balanced, fewest cut faces).
  Decomposition(const Index3& cells, int ranks, std::array<int, 3> dims = {0, 0, 0},
                std::array<bool, 3> periodic = {false, false, false});

  int ranks() const { return ranks_; }
  const std::array<int, 3>& dims() const { return dims_; }
  const Index3& cells() const { return cells_; }
  const std::array<bool, 3>& periodic() const { return periodic_; }
  Box domain() const { return Box{{0, 0, 0}, cells_}; }

  const Box& block(int rank) const { return blocks_[rank]; }
  // Rank owning a cell; the cell is wrapped on periodic axes first. -1 outside.
  int owner(Index3 cell) const;
  // Wrap a cell index into the domain on periodic axes.
  Index3 wrap(Index3 cell) const;
  // Ghost width per axis for a requested width: zero on axes one cell thick.
  Index3 ghost(int width) const;
  // Periodic image shifts (multiples of the domain size) to try when
  // intersecting boxes that may wrap: {0} on non-periodic axes, {-n, 0, n} else.
  std::vector<Index3> image_shifts() const;
  // The part of `b` that lies in the domain on non-periodic axes.
  Box clip(const Box& b) const;

 private:
  Index3 cells_{1, 1, 1};
  int ranks_ = 1;
  std::array<int, 3> dims_{1, 1, 1};
  std::array<bool, 3> periodic_{false, false, false};
  std::array<std::vector<long>, 3> cuts_;  // cut positions per axis, size dims+1
  std::vector<Box> blocks_;
};

// Balanced block counts per axis for `ranks` blocks of `cells`, minimising the
// cut area; axes with one cell get one block.
std::array<int, 3> choose_dims(const Index3& cells, int ranks);

}  // namespace coflow::coupler
