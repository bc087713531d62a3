// Trilinear interpolation and spreading stencil of the point method (seed 003
// §4.2.2: the fluid at a particle, and the particle's momentum source back to
// the same cells with the same weights, so that spreading conserves momentum).
#pragma once

#include <algorithm>
#include <cmath>

#include "coflow/decomposition.hpp"
#include "coflow/run_config.hpp"

namespace coflow::immersed {

// The 8 cells around a point and their trilinear weights (cell centres at
// lower + (i + 1/2) h, h per axis). Non-periodic axes clamp to the domain, so
// that a point between the last centre and a face gives that cell the whole
// weight (spreading stays conservative); see `extrapolate` for
// interpolation. On periodic axes the indices may be -1 or n (the exchange
// wraps them), taken from the cell the point exchange routes the point to
// (its floor, wrapped), so that they lie in that rank's ghost layer. An axis
// of one cell gives that cell the whole weight.
struct Stencil {
  coupler::Index3 cell[8];
  double weight[8];
};

//
// extrapolate (interpolation only): on a non-periodic axis a point between a
// face and the first or last cell centre takes the line through the two
// nearest centres (a weight outside [0, 1]), so that interpolation stays
// exact for linear fields up to the face; the weights still add up to one.
// Spreading keeps the clamped stencil, whose weights are never negative.
inline Stencil stencil(const double* x, const config::DomainParams& dom, const config::Vec3& h,
                       bool extrapolate = false) {
  long i0[3];
  double t[3];
  for (int d = 0; d < 3; ++d) {
    const long n = dom.cells[d];
    double s = (x[d] - dom.lower[d]) / h[d];
    if (dom.periodic[d]) {  // the routed cell: floor(s) wrapped into [0, n)
      const double wraps = std::floor(std::floor(s) / static_cast<double>(n));
      s -= wraps * static_cast<double>(n);
    }
    s -= 0.5;
    i0[d] = n == 1 ? 0 : static_cast<long>(std::floor(s));
    if (extrapolate && !dom.periodic[d] && n >= 2) i0[d] = std::clamp(i0[d], 0L, n - 2);
    t[d] = n == 1 ? 0.0 : s - static_cast<double>(i0[d]);
    if (extrapolate)
      t[d] = std::clamp(t[d], -0.5, 1.5);  // at most to the faces (a point outside stays there)
  }
  Stencil st;
  for (int c = 0; c < 8; ++c) {
    double w = 1.0;
    for (int d = 0; d < 3; ++d) {
      const int up = (c >> d) & 1;
      long i = i0[d] + up;
      w *= up ? t[d] : 1.0 - t[d];
      if (!dom.periodic[d] || dom.cells[d] == 1) i = std::clamp(i, 0L, static_cast<long>(dom.cells[d]) - 1);
      st.cell[c][d] = i;
    }
    st.weight[c] = w;
  }
  return st;
}

}  // namespace coflow::immersed
