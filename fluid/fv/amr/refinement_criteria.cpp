#include "fluid/fv/amr/refinement_criteria.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "fluid/fv/amr/composite_grid.hpp"

namespace coflow::fluid::fv::amr {
namespace {

int mark(double value, double refine_above, double coarsen_below) {
  if (!(value <= refine_above)) return 1;  // NaN refines: never hides a blow-up by coarsening it
  return value < coarsen_below ? -1 : 0;
}

}  // namespace

std::vector<int> mark_by_variation(const Forest& forest, int component, double refine_above,
                                   double coarsen_below) {
  const auto& spec = forest.spec();
  const long n = spec.patch, nz = spec.dims == 3 ? n : 1, nc = spec.components;
  std::vector<int> marks(forest.leaves().size(), 0);
  for (std::size_t l = 0; l < marks.size(); ++l) {
    const auto v = forest.data(l);
    auto at = [&](long i, long j, long k) {
      return v[static_cast<std::size_t>(((k * n + j) * n + i) * nc + component)];
    };
    double largest = 0.0;
    for (long k = 0; k < nz; ++k)
      for (long j = 0; j < n; ++j)
        for (long i = 0; i < n; ++i) {
          const double c = at(i, j, k);
          if (i + 1 < n) largest = std::max(largest, std::fabs(at(i + 1, j, k) - c));
          if (j + 1 < n) largest = std::max(largest, std::fabs(at(i, j + 1, k) - c));
          if (k + 1 < nz) largest = std::max(largest, std::fabs(at(i, j, k + 1) - c));
          if (std::isnan(c)) largest = c;
        }
    marks[l] = mark(largest, refine_above, coarsen_below);
  }
  return marks;
}

std::vector<int> mark_by_magnitude(const Forest& forest, int component, double refine_above,
                                   double coarsen_below) {
  const auto nc = static_cast<std::size_t>(forest.spec().components);
  std::vector<int> marks(forest.leaves().size(), 0);
  for (std::size_t l = 0; l < marks.size(); ++l) {
    const auto v = forest.data(l);
    double largest = 0.0;
    for (std::size_t c = static_cast<std::size_t>(component); c < v.size(); c += nc)
      largest = std::isnan(v[c]) ? v[c] : std::max(largest, std::fabs(v[c]));
    marks[l] = mark(largest, refine_above, coarsen_below);
  }
  return marks;
}

namespace {

// Whether any leaf at `level` or finer covers a patch of `level` next to the
// box [lo, lo + 4) of patches (per axis) there, periodic images wrapped.
bool finer_around(const CompositeGrid& g, int level, const Index3& lo) {
  const int dims = g.dims();
  const long n = g.patch();
  const int span = 6, total = dims == 3 ? span * span * span : span * span;
  for (int k = 0; k < total; ++k) {
    Index3 p{0, 0, 0};
    bool ring = false;
    for (int d = 0, rest = k; d < dims; ++d, rest /= span) {
      const int o = rest % span - 1;  // -1 .. 4
      ring = ring || o < 0 || o > 3;
      p[static_cast<std::size_t>(d)] = lo[static_cast<std::size_t>(d)] + o;
    }
    if (!ring) continue;
    Index3 cell{0, 0, 0};
    for (int d = 0; d < dims; ++d) cell[static_cast<std::size_t>(d)] = p[static_cast<std::size_t>(d)] * n;
    const auto c = g.cover(level, cell);
    if (c == CompositeGrid::Cover::leaf || c == CompositeGrid::Cover::finer) return true;
  }
  return false;
}

}  // namespace

namespace {

// A leaf's box in space.
std::pair<std::array<double, 3>, std::array<double, 3>> leaf_box(const CompositeGrid& g, const Leaf& leaf) {
  const double size = g.spacing(leaf.level) * g.patch();
  std::array<double, 3> lo{0.0, 0.0, 0.0}, hi{0.0, 0.0, 0.0};
  for (int d = 0; d < 3; ++d) {
    const auto i = static_cast<std::size_t>(d);
    lo[i] = g.origin()[i] + (d < g.dims() ? static_cast<double>(leaf.patch[i]) * size : 0.0);
    hi[i] = lo[i] + (d < g.dims() ? size : 0.0);
  }
  return {lo, hi};
}

}  // namespace

std::vector<int> mark_in_box(const CompositeGrid& g, const std::array<double, 3>& lo,
                             const std::array<double, 3>& hi) {
  const auto& leaves = g.forest().leaves();
  std::vector<int> marks(leaves.size(), -1);
  for (std::size_t l = 0; l < leaves.size(); ++l) {
    const auto [a, b] = leaf_box(g, leaves[l]);
    bool overlap = true;
    for (int d = 0; d < g.dims(); ++d) {
      const auto i = static_cast<std::size_t>(d);
      overlap = overlap && a[i] < hi[i] && b[i] > lo[i];
    }
    if (overlap) marks[l] = 1;
  }
  return marks;
}

std::vector<int> mark_near_walls(const CompositeGrid& g, double distance) {
  const auto& leaves = g.forest().leaves();
  const auto& spec = g.forest().spec();
  std::vector<int> marks(leaves.size(), -1);
  for (std::size_t l = 0; l < leaves.size(); ++l) {
    const auto [a, b] = leaf_box(g, leaves[l]);
    for (int d = 0; d < g.dims(); ++d) {
      const auto i = static_cast<std::size_t>(d);
      if (spec.periodic[i]) continue;
      const double low = g.origin()[i], high = low + g.spacing(0) * g.patch() * spec.trees[i];
      if (a[i] - low < distance || high - b[i] < distance) marks[l] = 1;
    }
  }
  return marks;
}

std::vector<int> mark_at_points(const CompositeGrid& g, const std::vector<std::array<double, 3>>& points) {
  std::vector<int> marks(g.forest().leaves().size(), -1);
  for (const auto& p : points) {
    long cell = 0;
    if (g.locate(p, &cell)) marks[static_cast<std::size_t>(cell / g.cells_per_patch())] = 1;
  }
  return marks;
}

void keep_coarsening_balanced(const CompositeGrid& g, std::vector<int>& marks) {
  const auto& leaves = g.forest().leaves();
  for (std::size_t l = 0; l < marks.size(); ++l) {
    if (marks[l] >= 0 || leaves[l].level == 0) continue;
    // The parent's region at two levels finer: 4 patches per axis from 4 x (parent index).
    Index3 lo{0, 0, 0};
    for (int d = 0; d < g.dims(); ++d)
      lo[static_cast<std::size_t>(d)] = (leaves[l].patch[static_cast<std::size_t>(d)] >> 1) * 4;
    if (finer_around(g, leaves[l].level + 1, lo)) marks[l] = 0;
  }
}

std::vector<int> combine_marks(const std::vector<std::vector<int>>& marks) {
  if (marks.empty()) return {};
  std::vector<int> out(marks.front().size(), -1);
  for (std::size_t l = 0; l < out.size(); ++l)
    for (const auto& m : marks) {
      if (m[l] > 0)
        out[l] = 1;
      else if (m[l] == 0 && out[l] < 0)
        out[l] = 0;
    }
  return out;
}

}  // namespace coflow::fluid::fv::amr
