#include "fluid/solid_surface.hpp"

#include <algorithm>
#include <cmath>

namespace coflow::fluid {

namespace {

constexpr double kNone = 2.0;  // no entry on the segment

// The sphere's (a disc's, `planar`: z ignored) first entry on a + t d.
double sphere_entry(const SolidParams& s, const stl::V3& a, const stl::V3& d) {
  stl::V3 ac(a[0] - s.centre.values.at(0), a[1] - s.centre.values.at(1), a[2] - s.centre.values.at(2));
  stl::V3 dd = d;
  if (s.planar) ac[2] = dd[2] = 0.0;
  const double A = dd.squaredNorm(), B = 2.0 * dd.dot(ac), C = ac.squaredNorm() - s.radius * s.radius;
  const double disc = B * B - 4.0 * A * C;
  if (A == 0.0 || disc < 0.0) return kNone;
  const double t = (-B - std::sqrt(disc)) / (2.0 * A);
  return t >= 0.0 && t <= 1.0 ? t : (C <= 0.0 ? 0.0 : kNone);
}

// The box's first entry on a + t d (slabs).
double box_entry(const SolidParams& s, const stl::V3& a, const stl::V3& d) {
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 3; ++k) {
    const double lo = s.lower.values.at(k), hi = s.upper.values.at(k);
    if (d[k] == 0.0) {
      if (a[k] < lo || a[k] > hi) return kNone;
      continue;
    }
    double ta = (lo - a[k]) / d[k], tb = (hi - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1 ? t0 : kNone;
}

// Moller & Trumbore (1997): where a + t d meets triangle (p, q, r), t in
// [0, 1], the edges taken with a margin of 1e-12 of the triangle; else kNone.
double triangle_entry(const stl::V3& p, const stl::V3& q, const stl::V3& r, const stl::V3& a,
                      const stl::V3& d) {
  const stl::V3 e1 = q - p, e2 = r - p, s = d.cross(e2);
  const double det = e1.dot(s);
  if (std::abs(det) < 1e-300) return kNone;
  const stl::V3 w = a - p;
  const double u = w.dot(s) / det;
  const stl::V3 c = w.cross(e1);
  const double v = d.dot(c) / det, t = e2.dot(c) / det;
  constexpr double margin = 1e-12;
  if (u < -margin || v < -margin || u + v > 1.0 + margin || t < 0.0 || t > 1.0) return kNone;
  return t;
}

}  // namespace

SolidSurface::SolidSurface(const config::Config& cfg, const std::vector<SolidParams>& solids)
    : domain_(cfg.domain), solids_(solids) {
  const auto h = domain_.spacing();
  for (int k = 0; k < 3; ++k) h_[k] = h[k];
  for (const auto& s : solids_) {
    mesh_of_.push_back(s.kind == "mesh" ? static_cast<int>(meshes_.size()) : -1);
    if (s.kind != "mesh") continue;
    meshes_.push_back(load_solid_mesh(s));
    auto& bins = bins_.emplace_back();
    const auto& m = meshes_.back();
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      long lo[3], hi[3];
      for (int k = 0; k < 3; ++k) {
        double a = m.vertices[m.triangles[t][0]][k], b = a;
        for (int v = 1; v < 3; ++v) {
          a = std::min(a, m.vertices[m.triangles[t][v]][k]);
          b = std::max(b, m.vertices[m.triangles[t][v]][k]);
        }
        lo[k] = std::max(0L, static_cast<long>(std::floor((a - domain_.lower[k]) / h_[k])) - 1);
        hi[k] = std::min(static_cast<long>(domain_.cells[k]) - 1,
                         static_cast<long>(std::floor((b - domain_.lower[k]) / h_[k])) + 1);
      }
      for (long z = lo[2]; z <= hi[2]; ++z)
        for (long y = lo[1]; y <= hi[1]; ++y)
          for (long x = lo[0]; x <= hi[0]; ++x)
            bins[(z * domain_.cells[1] + y) * domain_.cells[0] + x].push_back(static_cast<int>(t));
    }
  }
}

long SolidSurface::bin(const stl::V3& x) const {
  long c[3];
  for (int k = 0; k < 3; ++k) {
    c[k] = static_cast<long>(std::floor((x[k] - domain_.lower[k]) / h_[k]));
    if (c[k] < 0 || c[k] >= domain_.cells[k]) return -1;
  }
  return (c[2] * domain_.cells[1] + c[1]) * domain_.cells[0] + c[0];
}

double SolidSurface::mesh_entry(std::size_t m, const stl::V3& a, const stl::V3& b) const {
  // A link reaches at most the next cell along each axis from b's, and the
  // triangles were binned into every cell their bounding box reaches and its
  // neighbours: b's cell holds all that the link can meet.
  double best = kNone;
  const auto& mesh = meshes_[m];
  const auto it = bins_[m].find(bin(b));
  if (it == bins_[m].end()) return best;
  for (const int t : it->second) {
    const auto& tri = mesh.triangles[static_cast<std::size_t>(t)];
    best = std::min(
        best, triangle_entry(mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]], a, b - a));
  }
  return best;
}

double SolidSurface::entry(std::size_t n, const stl::V3& a, const stl::V3& b) const {
  const SolidParams& s = solids_[n];
  if (s.kind == "sphere") return sphere_entry(s, a, b - a);
  if (s.kind == "box") return box_entry(s, a, b - a);
  if (s.kind == "mesh") return mesh_entry(static_cast<std::size_t>(mesh_of_[n]), a, b);
  return kNone;  // a voxel image: no surface but its voxels' faces
}

double SolidSurface::fraction(const std::array<long, 3>& cell, const int* e, int id) const {
  stl::V3 a, b;
  for (int k = 0; k < 3; ++k) {
    // Along an axis of one cell (periodic) the lattice's link stays in the
    // plane: D3Q19 on one cell along z streams (1, 0, 1) to the cell at +x.
    const int ek = domain_.cells[k] == 1 ? 0 : e[k];
    long to = cell[k] + ek;
    if (domain_.periodic[k]) to = (to % domain_.cells[k] + domain_.cells[k]) % domain_.cells[k];
    b[k] = domain_.lower[k] + (static_cast<double>(to) + 0.5) * h_[k];
    a[k] = b[k] - ek * h_[k];
  }
  double t = solids_.at(static_cast<std::size_t>(id - 1)).kind == "voxels" ? 0.5 : kNone;
  for (std::size_t n = 0; n < solids_.size(); ++n) t = std::min(t, entry(n, a, b));
  return t <= 1.0 ? t : 0.5;
}

}  // namespace coflow::fluid
