#include "fluid/fv/speed_bounds.hpp"

#include <algorithm>
#include <cmath>

namespace coflow::fluid::fv {

std::array<double, 3> boundary_speeds(const FluidParams& fluid, const config::Config& cfg) {
  std::array<double, 3> out{0.0, 0.0, 0.0};
  const auto& d = cfg.domain;
  const int dims = d.two_dimensional() ? 2 : 3;
  for (int f = 0; f < 2 * dims; ++f) {
    const int a = f / 2;
    if (d.periodic[static_cast<std::size_t>(a)] || d.cells[static_cast<std::size_t>(a)] == 1) continue;
    const BoundaryParams b = fluid.boundary(f, cfg);
    if (b.type != "velocity") continue;
    double factor = 1.0;
    if (b.profile != "uniform") {  // the largest |factor| at the face's cell centres and corners
      factor = 0.0;
      const int e1 = (a + 1) % 3, e2 = (a + 2) % 3;
      // Along an axis of n cells: its 2n + 1 half-cell points (one, the
      // middle, along an axis of one cell).
      auto points = [&](int e) {
        return d.cells[static_cast<std::size_t>(e)] > 1 ? 2 * d.cells[static_cast<std::size_t>(e)] + 1 : 1L;
      };
      auto place = [&](int e, long i) {
        const long n = d.cells[static_cast<std::size_t>(e)];
        return n > 1 ? static_cast<double>(i) / static_cast<double>(2 * n) : 0.5;
      };
      double s[3];
      s[a] = f % 2 == 0 ? 0.0 : 1.0;
      for (long i = 0; i < points(e1); ++i)
        for (long j = 0; j < points(e2); ++j) {
          s[e1] = place(e1, i);
          s[e2] = place(e2, j);
          factor = std::max(factor, std::abs(b.profile_factor(f, s, cfg, 0.0)));
        }
    }
    for (std::size_t c = 0; c < 3; ++c) out[c] = std::max(out[c], std::abs(b.value.values[c]) * factor);
  }
  if (dims == 2) out[2] = 0.0;
  return out;
}

MarkerSpeeds marker_speeds(const ibm::MarkerSet& markers) {
  MarkerSpeeds out;
  for (const auto& m : markers.markers)
    for (std::size_t c = 0; c < 3; ++c) {
      out.u[c] = std::max(out.u[c], std::abs(m.u[c]));
      out.a[c] = std::max(out.a[c], std::abs(m.a[c]));
    }
  return out;
}

}  // namespace coflow::fluid::fv
