#include "fluid/fv/amr/refinement_criteria.hpp"

#include <algorithm>
#include <cmath>

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
