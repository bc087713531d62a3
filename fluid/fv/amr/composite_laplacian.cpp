#include "fluid/fv/amr/composite_laplacian.hpp"

#include <algorithm>

namespace coflow::fluid::fv::amr {
namespace {

Index3 shifted(Index3 i, int axis, long by) {
  i[axis] += by;
  return i;
}

// Sorts a stencil by id and merges repeated ids.
void merge(Stencil& s) {
  std::sort(s.begin(), s.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Stencil m;
  for (const auto& e : s) {
    if (!m.empty() && m.back().first == e.first)
      m.back().second += e.second;
    else
      m.push_back(e);
  }
  s.swap(m);
}

// The coarse cell's flux through a face whose other side is finer: minus the
// mean of the fine cells' fluxes through it (gradient * h_fine each).
void coarse_side_face(const CompositeGrid& g, const CompositeGrid::Cell& c, int axis, int side,
                      Stencil& row) {
  const int dims = g.dims();
  const int faces = 1 << (dims - 1);
  const double h_c = g.spacing(c.level), h_f = g.spacing(c.level + 1);
  for (int f = 0; f < faces; ++f) {
    CompositeGrid::Cell fine{c.level + 1, {0, 0, 0}};
    int bit = 0;
    for (int d = 0; d < dims; ++d) {
      if (d == axis)
        fine.index[d] = 2 * (c.index[d] + side) + (side > 0 ? 0 : 1);
      else
        fine.index[d] = 2 * c.index[d] + ((f >> bit++) & 1);
    }
    Stencil flux;
    g.coarse_fine_gradient(fine, axis, -side, flux);
    add(row, flux, -1.0 / (faces * h_f * h_c));
  }
}

}  // namespace

CompositeLaplacian assemble_laplacian(const CompositeGrid& g, const std::array<FaceCondition, 6>& faces) {
  CompositeLaplacian L;
  const long n = g.local_cells();
  L.rows.resize(static_cast<std::size_t>(n));
  for (long c = 0; c < n; ++c) {
    const auto cell = g.local_cell(c);
    const double h = g.spacing(cell.level);
    const long self = g.first_cell() + c;
    Stencil& row = L.rows[static_cast<std::size_t>(c)];
    for (int axis = 0; axis < g.dims(); ++axis)
      for (int side : {-1, 1}) {
        const Index3 nb = shifted(cell.index, axis, side);
        long id = 0;
        switch (g.cover(cell.level, nb, &id)) {
          case CompositeGrid::Cover::leaf:
            row.emplace_back(id, 1.0 / (h * h));
            row.emplace_back(self, -1.0 / (h * h));
            break;
          case CompositeGrid::Cover::coarser: {
            Stencil flux;
            g.coarse_fine_gradient(cell, axis, side, flux);
            add(row, flux, 1.0 / (h * h));
            break;
          }
          case CompositeGrid::Cover::finer:
            coarse_side_face(g, cell, axis, side, row);
            break;
          case CompositeGrid::Cover::outside: {
            const int face = 2 * axis + (side > 0);
            auto point = g.centre(cell);
            point[axis] += 0.5 * side * h;
            if (faces[face] == FaceCondition::dirichlet) {  // ghost 2 g - phi
              row.emplace_back(self, -2.0 / (h * h));
              L.boundary.push_back({c, point, 2.0 / (h * h), face});
            } else {
              L.boundary.push_back({c, point, 1.0 / h, face});
            }
            break;
          }
        }
      }
    merge(row);
  }
  return L;
}

}  // namespace coflow::fluid::fv::amr
