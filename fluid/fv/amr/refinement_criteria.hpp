// Where fv's adaptive grid refines (seed 003 §4.1.1: where vorticity,
// turbulence, walls or particles demand it): marks per local leaf for
// Forest::adapt, +1 refine, -1 coarsen, 0 keep. A criterion reads a field
// kept on the leaves (vorticity magnitude, k, a wall or body distance, a
// particle count per cell) or the leaves' positions.
#pragma once

#include <array>
#include <vector>

#include "fluid/fv/amr/forest.hpp"

namespace coflow::fluid::fv::amr {

// By the variation of one component across the leaf's cells: the largest
// difference between neighbouring cells of the patch, refined above
// `refine_above`, coarsened below `coarsen_below`.
std::vector<int> mark_by_variation(const Forest& forest, int component, double refine_above,
                                   double coarsen_below);

// By the size of a value (|vorticity|, k, particles per cell): refined where
// a cell's value exceeds `refine_above`, coarsened where all are below
// `coarsen_below`.
std::vector<int> mark_by_magnitude(const Forest& forest, int component, double refine_above,
                                   double coarsen_below);

// Combines criteria: refine where any refines, coarsen where all coarsen.
std::vector<int> combine_marks(const std::vector<std::vector<int>>& marks);

class CompositeGrid;

// By geometry (`box`): refined where the leaf overlaps [lo, hi], coarsened
// elsewhere.
std::vector<int> mark_in_box(const CompositeGrid& grid, const std::array<double, 3>& lo,
                             const std::array<double, 3>& hi);
// Near walls (`walls`): refined where the leaf comes within `distance` of a
// non-periodic domain face, coarsened elsewhere.
std::vector<int> mark_near_walls(const CompositeGrid& grid, double distance);
// Where points are (`particles`, `bodies` by their markers): refined where a
// leaf holds at least one of `points` (this rank's or any rank's: points
// outside the local leaves are ignored), coarsened where it holds none.
std::vector<int> mark_at_points(const CompositeGrid& grid, const std::vector<std::array<double, 3>>& points);

// Withdraws the coarsening marks of leaves whose parent would touch a leaf
// two levels finer: 2:1 balance would refine the parent straight back,
// smoothing its values for nothing and forcing a rebuild. `grid` is the
// forest's grid as it is (its ghost leaves are the neighbours).
void keep_coarsening_balanced(const CompositeGrid& grid, std::vector<int>& marks);

}  // namespace coflow::fluid::fv::amr
