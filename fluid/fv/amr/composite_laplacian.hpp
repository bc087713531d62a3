// The cell-centred Laplacian on the composite grid, as matrix rows: the
// pressure Poisson operator of fv's projection (seed 003 §4.1) on refined
// grids. Fluxes through faces between cells of one level are plain
// differences; through a coarse-fine face each fine cell's flux uses the
// ghost value of CompositeGrid::coarse_fine_gradient, and the coarse cell's
// flux is the mean of its fine faces' fluxes (refluxing built into the
// operator), so the sum over all cells of volume times Laplacian telescopes
// to the domain's boundary: conservative to round-off across levels.
#pragma once

#include <array>
#include <vector>

#include "fluid/fv/amr/composite_faces.hpp"
#include "fluid/fv/amr/composite_grid.hpp"

namespace coflow::fluid::fv::amr {

enum class FaceCondition { dirichlet, neumann };

struct BoundaryFace {
  long cell = 0;                // local cell number
  std::array<double, 3> point;  // centre of the boundary face
  double coefficient = 0.0;     // (L phi)_cell gets coefficient * g(point)
  int face = 0;                 // 2 * axis + (side > 0)
};

struct CompositeLaplacian {
  // Rows of the local cells, each a stencil of global cell ids (merged, sorted).
  std::vector<Stencil> rows;
  // The boundary faces' known values' coefficients: g is the Dirichlet value
  // or the outward normal derivative (Neumann).
  std::vector<BoundaryFace> boundary;
};

// Assembles L on `grid`; `faces[2 * axis + (side > 0)]` says what holds on
// each non-periodic domain face.
CompositeLaplacian assemble_laplacian(const CompositeGrid& grid, const std::array<FaceCondition, 6>& faces);
// The same from the grid's faces already built (build_faces, ids global).
// With `coefficient` (per local cell, per sub-face in build_faces' order),
// div(a grad phi): each face's flux, and a boundary face's known value,
// times the face's a (the same number from both sides: conservative).
CompositeLaplacian assemble_laplacian(const CompositeGrid& grid,
                                      const std::vector<std::vector<SubFace>>& faces,
                                      const std::array<FaceCondition, 6>& conditions,
                                      const std::vector<std::vector<double>>* coefficient = nullptr);

}  // namespace coflow::fluid::fv::amr
