#include "fluid/mesh_voxels.hpp"

#include <algorithm>
#include <cmath>

namespace coflow::fluid {

namespace {

// The rows n in [0, count), at c0 + (n + 1/2 + offset) h, between lo and hi.
void rows_between(double lo, double hi, double c0, double h, double offset, long count, long& first,
                  long& last) {
  first = std::max(0L, static_cast<long>(std::ceil((lo - c0) / h - 0.5 - offset)));
  last = std::min(count - 1, static_cast<long>(std::floor((hi - c0) / h - 0.5 - offset)));
}

}  // namespace

std::vector<std::uint8_t> mesh_voxels(const stl::TriangleMesh& mesh, const config::DomainParams& d) {
  const auto h = d.spacing();
  const long nx = d.cells[0], ny = d.cells[1], nz = d.cells[2];
  // Offsets of the rays, in cells: irrational, so that no ray meets an edge.
  const double oy = 1e-7 * std::sqrt(2.0), oz = 1e-7 * std::sqrt(3.0);
  std::vector<std::vector<double>> crossings(static_cast<std::size_t>(ny * nz));
  for (const auto& t : mesh.triangles) {
    const stl::V3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const double det = (b[1] - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (b[2] - a[2]);
    if (det == 0.0) continue;  // edge-on to the rays
    long j0, j1, k0, k1;
    rows_between(std::min({a[1], b[1], c[1]}), std::max({a[1], b[1], c[1]}), d.lower[1], h[1], oy, ny, j0,
                 j1);
    rows_between(std::min({a[2], b[2], c[2]}), std::max({a[2], b[2], c[2]}), d.lower[2], h[2], oz, nz, k0,
                 k1);
    for (long k = k0; k <= k1; ++k)
      for (long j = j0; j <= j1; ++j) {
        const double y = d.lower[1] + (j + 0.5 + oy) * h[1], z = d.lower[2] + (k + 0.5 + oz) * h[2];
        // Barycentric coordinates of (y, z) in the projected triangle.
        const double u = ((y - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (z - a[2])) / det;
        const double v = ((b[1] - a[1]) * (z - a[2]) - (y - a[1]) * (b[2] - a[2])) / det;
        if (u < 0.0 || v < 0.0 || u + v > 1.0) continue;
        crossings[static_cast<std::size_t>(k * ny + j)].push_back(a[0] + u * (b[0] - a[0]) +
                                                                  v * (c[0] - a[0]));
      }
  }
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(nx * ny * nz), 0);
  for (long k = 0; k < nz; ++k)
    for (long j = 0; j < ny; ++j) {
      auto& xs = crossings[static_cast<std::size_t>(k * ny + j)];
      std::sort(xs.begin(), xs.end());
      std::size_t passed = 0;
      for (long i = 0; i < nx; ++i) {
        const double x = d.lower[0] + (i + 0.5) * h[0];
        while (passed < xs.size() && xs[passed] < x) ++passed;
        inside[static_cast<std::size_t>((k * ny + j) * nx + i)] = passed % 2;
      }
    }
  return inside;
}

}  // namespace coflow::fluid
