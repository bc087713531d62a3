#include "fluid/fv/amr/composite_faces.hpp"

namespace coflow::fluid::fv::amr {
namespace {

// The value at the face between cell `c` and its neighbour on `side`, both
// leaves of one level: cubic through two cells on each side ((-1, 9, 9, -1)
// / 16), or quadratic through three where one outer cell has no value at
// this level, or the mean of the two. Third order where it can: the cells'
// gradients by Gauss's theorem and the advected values gain from it; beside
// a coarse-fine face the gradient stays first order (the coarse face's value
// is the mean of its fine faces', docs/validation.md).
Stencil same_level_value(const CompositeGrid& g, const CompositeGrid::Cell& c, int axis, int side) {
  // Built from the lower cell whichever of the two asks, so that both list
  // the same entries in the same order and their sums have the same bits.
  const Index3 near = side > 0 ? c.index : shifted(c.index, axis, -1), far = shifted(near, axis, 1);
  Stencil a, b, out;
  g.value(c.level, near, out, 0.5);
  g.value(c.level, far, out, 0.5);
  const bool before = g.value(c.level, shifted(near, axis, -1), a);
  const bool after = g.value(c.level, shifted(far, axis, 1), b);
  if (before && after) {
    for (auto& e : out) e.second = 9.0 / 16.0;
    add(out, a, -1.0 / 16.0);
    add(out, b, -1.0 / 16.0);
  } else if (before) {  // nodes -1, 0, 1 at 1/2: (-1, 6, 3) / 8
    out[0].second = 6.0 / 8.0;
    out[1].second = 3.0 / 8.0;
    add(out, a, -1.0 / 8.0);
  } else if (after) {
    out[0].second = 3.0 / 8.0;
    out[1].second = 6.0 / 8.0;
    add(out, b, -1.0 / 8.0);
  }
  return out;
}

// The fine cell `fine`'s face towards a coarser neighbour: ghost - phi_0 = G
// (CompositeGrid::coarse_fine_gradient), gradient G / h; the value on the
// face from the quadratic through the two fine cells (at -1.5 and -0.5 fine
// spacings) and the coarse value interpolated along the face (at +1), whose
// weights are (-1/5, 1, 1/5); G holds (-1/5, -1/3, 8/15) of the same three.
void fine_side(const CompositeGrid& g, const CompositeGrid::Cell& fine, int axis, int side, SubFace& f) {
  Stencil ghost_minus_centre;
  g.coarse_fine_gradient(fine, axis, side, ghost_minus_centre);
  const double h = g.spacing(fine.level);
  add(f.gradient, ghost_minus_centre, 1.0 / h);
  // value = phi_0 + 0.2 phi_1 ... written as  3/8 G + (1 + 1/8) phi_0 - 0.125 phi_1:
  // 3/8 (-1/5, -1/3, 8/15) + (-1/8, 9/8, 0) = (-1/5, 1, 1/5).
  add(f.value, ghost_minus_centre, 3.0 / 8.0);
  if (!g.value(fine.level, fine.index, f.value, 9.0 / 8.0) ||
      !g.value(fine.level, shifted(fine.index, axis, -side), f.value, -1.0 / 8.0))
    throw std::logic_error("refinement: a fine cell without its value");
  Index3 coarse = shifted(fine.index, axis, side);
  for (int d = 0; d < g.dims(); ++d)
    coarse[static_cast<std::size_t>(d)] >>= 1;  // floor (periodic images: -1)
  if (g.cover(fine.level - 1, coarse, &f.across) != CompositeGrid::Cover::leaf)
    throw std::logic_error("refinement: a coarse-fine face without its coarse cell");
  f.across_level = -1;
  f.across_index = coarse;
}

// A coarse cell's face towards finer cells: one sub-face per fine face, the
// fine side's stencils with the gradient negated.
void coarse_side(const CompositeGrid& g, const CompositeGrid::Cell& c, int axis, int side,
                 std::vector<SubFace>& out) {
  const int dims = g.dims(), pieces = 1 << (dims - 1);
  for (int p = 0; p < pieces; ++p) {
    CompositeGrid::Cell fine{c.level + 1, {0, 0, 0}};
    int bit = 0;
    for (int d = 0; d < dims; ++d) {
      if (d == axis)
        fine.index[d] = 2 * (c.index[d] + side) + (side > 0 ? 0 : 1);
      else
        fine.index[d] = 2 * c.index[d] + ((p >> bit++) & 1);
    }
    SubFace from_fine;
    fine_side(g, fine, axis, -side, from_fine);
    SubFace f{axis, side, 1.0 / pieces, false, {}, std::move(from_fine.value), -1, -1, 1, fine.index};
    add(f.gradient, from_fine.gradient, -1.0);
    if (g.cover(fine.level, fine.index, &f.across) != CompositeGrid::Cover::leaf)
      throw std::logic_error("refinement: a coarse-fine face without its fine cell");
    out.push_back(std::move(f));
  }
}

}  // namespace

std::vector<std::vector<SubFace>> build_faces(const CompositeGrid& g) {
  const long n = g.local_cells();
  std::vector<std::vector<SubFace>> faces(static_cast<std::size_t>(n));
  for (long c = 0; c < n; ++c) {
    const auto cell = g.local_cell(c);
    const double h = g.spacing(cell.level);
    const long self = g.first_cell() + c;
    auto& out = faces[static_cast<std::size_t>(c)];
    for (int axis = 0; axis < g.dims(); ++axis)
      for (int side : {-1, 1}) {
        long id = 0;
        switch (g.cover(cell.level, shifted(cell.index, axis, side), &id)) {
          case CompositeGrid::Cover::leaf:
            out.push_back({axis,
                           side,
                           1.0,
                           false,
                           {{id, 1.0 / h}, {self, -1.0 / h}},
                           same_level_value(g, cell, axis, side),
                           id,
                           -1,
                           0,
                           shifted(cell.index, axis, side)});
            break;
          case CompositeGrid::Cover::coarser:
            out.push_back({axis, side, 1.0, false, {}, {}});
            fine_side(g, cell, axis, side, out.back());
            break;
          case CompositeGrid::Cover::finer:
            coarse_side(g, cell, axis, side, out);
            break;
          case CompositeGrid::Cover::outside:
            out.push_back({axis, side, 1.0, true, {}, {}});
            break;
        }
      }
  }
  return faces;
}

}  // namespace coflow::fluid::fv::amr
