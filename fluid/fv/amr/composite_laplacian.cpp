#include "fluid/fv/amr/composite_laplacian.hpp"

#include <algorithm>

#include "fluid/fv/amr/composite_faces.hpp"

namespace coflow::fluid::fv::amr {
namespace {

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

}  // namespace

CompositeLaplacian assemble_laplacian(const CompositeGrid& g,
                                      const std::array<FaceCondition, 6>& conditions) {
  return assemble_laplacian(g, build_faces(g), conditions);
}

CompositeLaplacian assemble_laplacian(const CompositeGrid& g, const std::vector<std::vector<SubFace>>& faces,
                                      const std::array<FaceCondition, 6>& conditions,
                                      const std::vector<std::vector<double>>* coefficient) {
  CompositeLaplacian L;
  L.rows.resize(faces.size());
  for (std::size_t c = 0; c < faces.size(); ++c) {
    const auto cell = g.local_cell(static_cast<long>(c));
    const double h = g.spacing(cell.level);
    const long self = g.first_cell() + static_cast<long>(c);
    Stencil& row = L.rows[c];
    for (std::size_t s = 0; s < faces[c].size(); ++s) {
      const auto& f = faces[c][s];
      const double a = coefficient ? (*coefficient)[c][s] : 1.0;
      if (!f.wall) {
        add(row, f.gradient, a * f.fraction / h);
        continue;
      }
      const int face = 2 * f.axis + (f.side > 0);
      auto point = g.centre(cell);
      point[f.axis] += 0.5 * f.side * h;
      if (conditions[face] == FaceCondition::dirichlet) {  // ghost 2 g - phi
        row.emplace_back(self, -2.0 * a / (h * h));
        L.boundary.push_back({static_cast<long>(c), point, 2.0 * a / (h * h), face});
      } else {
        L.boundary.push_back({static_cast<long>(c), point, a / h, face});
      }
    }
    merge(row);
  }
  return L;
}

}  // namespace coflow::fluid::fv::amr
