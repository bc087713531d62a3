// The cells of fv's adaptive grid: every leaf of the forest (forest.hpp)
// holds a patch of n x n (x n) cells, so the grid is block-structured within
// each leaf and the levels differ by a ratio of 2 (seed 003 §4.1.1). The
// composite grid is the set of all leaves' cells (no cell is covered by a
// finer one: only leaves hold cells).
//
// Cell ids are global and fixed by the forest's order: leaf g's cells are
// g * n^d ... (g + 1) * n^d - 1, x fastest. A rank owns its leaves' cells,
// a contiguous range, and knows its ghost leaves' ids without messages.
//
// Values at a point of a level are stencils (linear combinations of cell
// ids): where the point's cell is a leaf cell of that level it is that cell;
// where the region is finer, the mean of the finer cells (conservative
// restriction); where coarser, no value (the operators then take one-sided
// stencils). The coarse-fine interface's ghost values, built from them,
// follow Martin & Cartwright (1996): quadratic interpolation of the coarse
// values along the interface, then quadratic interpolation normal to it
// through two fine cells (seed 003 §4.1.1 interpolates across levels
// quadratically).
#pragma once

#include <array>
#include <unordered_map>
#include <utility>
#include <vector>

#include "fluid/fv/amr/forest.hpp"

namespace coflow::fluid::fv::amr {

// A linear combination of cells: (global cell id, weight).
using Stencil = std::vector<std::pair<long, double>>;

struct GridGeometry {
  std::array<double, 3> origin{0.0, 0.0, 0.0};
  double tree_size = 1.0;  // edge of one tree (a level-0 patch)
};

// Valid while its forest does not adapt (rebuild it after a regrid).
class CompositeGrid {
 public:
  CompositeGrid(const Forest& forest, const GridGeometry& geometry);

  enum class Cover { leaf, finer, coarser, outside };
  struct Cell {
    int level = 0;
    Index3 index{0, 0, 0};  // among all cells of its level over the brick
  };

  int dims() const { return dims_; }
  int patch() const { return n_; }
  long cells_per_patch() const { return cells_per_patch_; }
  long local_cells() const { return static_cast<long>(forest_.leaves().size()) * cells_per_patch_; }
  long first_cell() const { return forest_.first_leaf() * cells_per_patch_; }
  long global_cells() const { return forest_.global_leaves() * cells_per_patch_; }
  const Forest& forest() const { return forest_; }

  // The local cell with local number c (0 .. local_cells()-1).
  Cell local_cell(long c) const;
  const std::array<double, 3>& origin() const { return geometry_.origin; }
  double spacing(int level) const { return geometry_.tree_size / (static_cast<double>(n_) * (1L << level)); }
  std::array<double, 3> centre(const Cell& c) const;
  // Cells of a level per axis over the brick.
  long extent(int level, int axis) const;

  // Who covers the cell `index` of `level` (periodic images wrapped); for
  // `leaf`, *id is its global id.
  Cover cover(int level, Index3 index, long* id = nullptr) const;
  // The value at the centre of cell `index` of `level`: a leaf cell, or the
  // mean of the finer cells in it; false where coarser or outside.
  bool value(int level, const Index3& index, Stencil& out, double weight = 1.0) const;
  // The fine cell `fine`'s ghost value across its face (axis, side = -1 or
  // +1) where the neighbour is one level coarser (Martin & Cartwright):
  // returns the flux (d phi / d n) * h_fine through that face as a stencil.
  void coarse_fine_gradient(const Cell& fine, int axis, int side, Stencil& out) const;

  // The local leaf cell containing point x (the finest cell there: the
  // composite grid's cells do not overlap); false where that cell belongs
  // to another rank. Periodic images are wrapped.
  bool locate(std::array<double, 3> x, long* local) const;

  // Where cell `id` sits in a field gathered with its ghosts: the local cells
  // first, then the ghost leaves' cells in the forest's ghost order.
  long slot(long id) const;
  long slots() const { return local_cells() + static_cast<long>(forest_.ghosts().size()) * cells_per_patch_; }
  // The forest's component q on the local and ghost cells, by slot (the
  // forest's ghosts exchanged first).
  void gather(int component, std::vector<double>& out) const;
  // A stencil with its ids turned into slots.
  Stencil to_slots(const Stencil& s) const;

 private:
  bool wrap(int level, Index3& index) const;  // false: outside a wall
  const Leaf* find(int level, const Index3& patch) const;
  double quadratic_along(int level, const Index3& c, int axis, double offset, Stencil& out, double w) const;
  void coarse_value_along_face(const Cell& coarse, const Cell& fine, int axis, Stencil& out, double w) const;

  const Forest& forest_;
  GridGeometry geometry_;
  int dims_;
  int n_;
  long cells_per_patch_;
  std::unordered_map<unsigned long long, const Leaf*> known_;  // local and ghost leaves by (level, patch)
  std::unordered_map<long, long> ghost_index_;                 // ghost leaves by global index
};

// `i` moved by `by` along `axis`.
inline Index3 shifted(Index3 i, int axis, long by) {
  i[static_cast<std::size_t>(axis)] += by;
  return i;
}

// The value of a stencil of slots on a field gathered with its ghosts.
inline double evaluate(const Stencil& s, const std::vector<double>& field) {
  double v = 0.0;
  for (const auto& [slot, w] : s) v += w * field[static_cast<std::size_t>(slot)];
  return v;
}

// Adds `w` times `s` to `out`.
inline void add(Stencil& out, const Stencil& s, double w) {
  for (const auto& [id, v] : s) out.emplace_back(id, v * w);
}

}  // namespace coflow::fluid::fv::amr
