#include "immersed/ibm/markers.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>

namespace coflow::ibm {

namespace {

struct Bin {
  double area = 0.0;
  Vec moment{0, 0, 0};  // sum of area x centroid
  Vec normal{0, 0, 0};  // sum of area x unit normal
};
using BinKey = std::tuple<long, long, long>;

// Splits triangle (a, b, c) into n^2 similar pieces and adds each piece's
// area (times `weight`) at its centroid to the bin holding that centroid.
void add_triangle(const stl::V3& a, const stl::V3& b, const stl::V3& c, double weight, const GridGeometry& g,
                  double spacing, std::map<BinKey, Bin>& bins) {
  // In 2D only the extent in the plane matters (a prism's length along z does not).
  auto length = [&](const stl::V3& v) { return g.dims == 2 ? std::hypot(v[0], v[1]) : v.norm(); };
  const double edge = std::max({length(b - a), length(c - b), length(a - c)});
  const double hmin = g.dims == 2 ? std::min(g.h[0], g.h[1]) : std::min({g.h[0], g.h[1], g.h[2]});
  const long n = std::max(1L, static_cast<long>(std::ceil(edge / (0.2 * spacing * hmin))));
  const stl::V3 e1 = (b - a) / static_cast<double>(n), e2 = (c - a) / static_cast<double>(n);
  const double piece = 0.5 * e1.cross(e2).norm() * weight;
  if (piece == 0.0) return;
  const stl::V3 normal = e1.cross(e2).normalized();
  auto add = [&](const stl::V3& centroid) {
    long key[3] = {0, 0, 0};
    for (int d = 0; d < g.dims; ++d)
      key[d] = static_cast<long>(std::floor((centroid[d] - g.lower[d]) / (spacing * g.h[d])));
    Bin& bin = bins[{key[0], key[1], key[2]}];
    bin.area += piece;
    for (int d = 0; d < 3; ++d) bin.moment[d] += piece * centroid[d];
    for (int d = 0; d < 3; ++d) bin.normal[d] += piece * normal[d];
  };
  for (long i = 0; i < n; ++i)
    for (long j = 0; i + j < n; ++j) {
      const stl::V3 p = a + static_cast<double>(i) * e1 + static_cast<double>(j) * e2;
      add(p + (e1 + e2) / 3.0);                             // the piece pointing like the triangle
      if (i + j + 1 < n) add(p + 2.0 * (e1 + e2) / 3.0);  // the one pointing the other way
    }
}

// A box holding less than half a full box's surface (a corner the surface
// clips) gives its pieces to the neighbouring box whose centroid is nearest:
// no marker then stands closer than about half a box to another with a
// sliver of area, which would make the forcing's system nearly singular.
void merge_slivers(std::map<BinKey, Bin>& bins, double full, int dims) {
  std::vector<std::pair<double, BinKey>> small;
  for (const auto& [key, bin] : bins)
    if (bin.area < 0.5 * full) small.push_back({bin.area, key});
  std::sort(small.begin(), small.end());
  for (const auto& [area, key] : small) {
    const auto it = bins.find(key);
    if (it == bins.end() || it->second.area >= 0.5 * full) continue;
    const Bin& b = it->second;
    auto centroid = [](const Bin& x, int d) { return x.moment[static_cast<std::size_t>(d)] / x.area; };
    std::map<BinKey, Bin>::iterator best = bins.end();
    double best_d2 = 0.0;
    const auto [i, j, k] = key;
    for (long dk = (dims == 3 ? -1 : 0); dk <= (dims == 3 ? 1 : 0); ++dk)
      for (long dj = -1; dj <= 1; ++dj)
        for (long di = -1; di <= 1; ++di) {
          if (di == 0 && dj == 0 && dk == 0) continue;
          const auto n = bins.find({i + di, j + dj, k + dk});
          if (n == bins.end()) continue;
          double d2 = 0.0;
          for (int d = 0; d < 3; ++d) d2 += std::pow(centroid(n->second, d) - centroid(b, d), 2);
          if (best == bins.end() || d2 < best_d2) best = n, best_d2 = d2;
        }
    if (best == bins.end()) continue;  // an isolated sliver: it stays a marker
    best->second.area += b.area;
    for (int d = 0; d < 3; ++d) {
      best->second.moment[static_cast<std::size_t>(d)] += b.moment[static_cast<std::size_t>(d)];
      best->second.normal[static_cast<std::size_t>(d)] += b.normal[static_cast<std::size_t>(d)];
    }
    bins.erase(it);
  }
}

}  // namespace

std::vector<SurfacePoint> sample_surface(const stl::TriangleMesh& mesh, const GridGeometry& g, double spacing) {
  if (spacing <= 0) throw std::invalid_argument("ibm: marker spacing must be positive");
  // In 2D the mesh is a prism along z: a triangle counts by its extent in the
  // plane (|n_xy|), and its area is scaled from the prism's length to the slab's.
  double zscale = 1.0;
  if (g.dims == 2) {
    double lo = mesh.vertices.empty() ? 0.0 : mesh.vertices[0][2], hi = lo;
    for (const auto& v : mesh.vertices) lo = std::min(lo, v[2]), hi = std::max(hi, v[2]);
    if (hi <= lo) throw std::runtime_error("ibm: a body of a 2D fluid is a prism along z; this mesh is flat in z");
    zscale = g.h[2] / (hi - lo);
  }
  std::map<BinKey, Bin> bins;
  for (const auto& t : mesh.triangles) {
    const stl::V3 &a = mesh.vertices[static_cast<std::size_t>(t[0])], &b = mesh.vertices[static_cast<std::size_t>(t[1])],
                  &c = mesh.vertices[static_cast<std::size_t>(t[2])];
    double weight = 1.0;
    if (g.dims == 2) {
      const stl::V3 n = (b - a).cross(c - a);
      const double norm = n.norm();
      weight = norm > 0 ? std::hypot(n[0], n[1]) / norm * zscale : 0.0;
    }
    if (weight > 0) add_triangle(a, b, c, weight, g, spacing, bins);
  }
  // A full box's surface: a plane across it (in 2D a line across the slab).
  const double full = g.dims == 2 ? spacing * std::sqrt(g.h[0] * g.h[1]) * g.h[2]
                                  : spacing * spacing * std::cbrt(g.h[0] * g.h[1] * g.h[2]) *
                                        std::cbrt(g.h[0] * g.h[1] * g.h[2]);
  merge_slivers(bins, full, g.dims);
  std::vector<SurfacePoint> out;
  out.reserve(bins.size());
  for (const auto& [key, bin] : bins) {
    if (bin.area <= 0) continue;
    SurfacePoint p;
    p.area = bin.area;
    for (int d = 0; d < 3; ++d) p.x[d] = bin.moment[d] / bin.area;
    const double n = std::sqrt(bin.normal[0] * bin.normal[0] + bin.normal[1] * bin.normal[1] +
                               bin.normal[2] * bin.normal[2]);
    if (n > 0)
      for (int d = 0; d < 3; ++d) p.normal[d] = bin.normal[d] / n;
    out.push_back(p);
  }
  return out;
}

MeshVolume mesh_volume(const stl::TriangleMesh& mesh) {
  MeshVolume m;
  stl::V3 moment = stl::V3::Zero();
  for (const auto& t : mesh.triangles) {
    const stl::V3 &a = mesh.vertices[static_cast<std::size_t>(t[0])], &b = mesh.vertices[static_cast<std::size_t>(t[1])],
                  &c = mesh.vertices[static_cast<std::size_t>(t[2])];
    const double v = a.dot(b.cross(c)) / 6.0;  // the tetrahedron with the origin
    m.volume += v;
    const stl::V3 sum = a + b + c;
    moment += v * sum / 4.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        m.second[static_cast<std::size_t>(3 * i + j)] +=
            v / 20.0 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + sum[i] * sum[j]);
  }
  if (m.volume != 0.0)
    for (int d = 0; d < 3; ++d) m.centroid[d] = moment[d] / m.volume;
  return m;
}

std::array<double, 9> inertia_about(const MeshVolume& v, const Vec& p) {
  std::array<double, 9> S{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) {
      const double mi = v.volume * v.centroid[i], mj = v.volume * v.centroid[j];
      S[3 * i + j] = v.second[3 * i + j] - p[i] * mj - mi * p[j] + v.volume * p[i] * p[j];
    }
  const double trace = S[0] + S[4] + S[8];
  for (std::size_t k = 0; k < 9; ++k) S[k] = (k % 4 == 0 ? trace : 0.0) - S[k];
  return S;
}

std::vector<double> MarkerSet::pack() const {
  std::vector<double> f{time, static_cast<double>(bodies.size()), static_cast<double>(markers.size())};
  f.reserve(3 + 9 * bodies.size() + 14 * markers.size());
  for (const auto& b : bodies) {
    f.insert(f.end(), b.centre.begin(), b.centre.end());
    f.insert(f.end(), b.velocity.begin(), b.velocity.end());
    f.insert(f.end(), b.acceleration.begin(), b.acceleration.end());
  }
  for (const auto& m : markers) {
    f.insert(f.end(), m.x.begin(), m.x.end());
    f.insert(f.end(), m.u.begin(), m.u.end());
    f.insert(f.end(), m.a.begin(), m.a.end());
    f.push_back(m.volume_ratio);
    f.push_back(static_cast<double>(m.body));
    f.insert(f.end(), m.n.begin(), m.n.end());
  }
  return f;
}

MarkerSet MarkerSet::unpack(const std::vector<double>& f) {
  MarkerSet s;
  if (f.size() < 3) throw std::runtime_error("ibm: a marker message without its header");
  s.time = f[0];
  const auto nb = static_cast<std::size_t>(f[1]), nm = static_cast<std::size_t>(f[2]);
  if (f.size() != 3 + 9 * nb + 14 * nm) throw std::runtime_error("ibm: a marker message of the wrong length");
  std::size_t at = 3;
  s.bodies.resize(nb);
  for (auto& b : s.bodies) {
    for (int d = 0; d < 3; ++d) b.centre[d] = f[at + d];
    for (int d = 0; d < 3; ++d) b.velocity[d] = f[at + 3 + d];
    for (int d = 0; d < 3; ++d) b.acceleration[d] = f[at + 6 + d];
    at += 9;
  }
  s.markers.resize(nm);
  for (auto& m : s.markers) {
    for (int d = 0; d < 3; ++d) m.x[d] = f[at + d];
    for (int d = 0; d < 3; ++d) m.u[d] = f[at + 3 + d];
    for (int d = 0; d < 3; ++d) m.a[d] = f[at + 6 + d];
    m.volume_ratio = f[at + 9];
    m.body = static_cast<int>(f[at + 10]);
    for (int d = 0; d < 3; ++d) m.n[d] = f[at + 11 + d];
    at += 14;
  }
  return s;
}

}  // namespace coflow::ibm
