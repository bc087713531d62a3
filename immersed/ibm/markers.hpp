// The markers of the immersed boundary (seed 003 §4.2.1): points on a body's
// surface, each with the volume Delta V_Gamma it stands for (eq. 4.10), and
// what the immersed component sends the fluid so that the fluid can iterate
// the multi-direct forcing on its own (ARCHITECTURE.md, Wave 2).
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "coflow/stl.hpp"

namespace coflow::ibm {

using Vec = std::array<double, 3>;

// The fluid grid as the markers see it: lower corner, cells, spacing, and
// whether it is 2D (one cell along z: the markers stand for the slab).
struct GridGeometry {
  Vec lower{0, 0, 0};
  std::array<long, 3> cells{1, 1, 1};
  Vec h{1, 1, 1};
  int dims = 3;
  double cell_volume() const { return h[0] * h[1] * h[2]; }
  // The thickness of a marker's shell, Delta V_Gamma = area x this: the
  // spacing (its geometric mean, in the plane in 2D).
  double shell() const { return dims == 2 ? std::sqrt(h[0] * h[1]) : std::cbrt(h[0] * h[1] * h[2]); }
};

// A piece of surface: its area-weighted centroid, its area and its mean
// outward normal (unit; the triangles' winding gives outward).
struct SurfacePoint {
  Vec x{0, 0, 0};
  double area = 0.0;
  Vec normal{0, 0, 0};
};

// Markers about `spacing` cells apart whatever the mesh's own triangles: the
// triangles are split until their edges are below a fifth of the spacing,
// the pieces gathered into boxes of `spacing` cells aligned with the grid,
// and each box's pieces become one point at their area-weighted centroid
// holding their total area; a box with less than half a full box's surface
// gives its pieces to the nearest neighbouring box. The areas sum to the
// mesh's area exactly.
std::vector<SurfacePoint> sample_surface(const stl::TriangleMesh& mesh, const GridGeometry& g, double spacing);

// The volume, centroid and second moments of a closed mesh (divergence
// theorem; outward normals give a positive volume): second[3 i + j] = the
// integral of x_i x_j over the body, x from the origin (each triangle's
// tetrahedron with the origin: V / 20 (sum_k p_k p_k^T + s s^T), s the sum
// of its vertices p_k; Tonon 2004, J. Math. Stat. 1:8).
struct MeshVolume {
  double volume = 0.0;
  Vec centroid{0, 0, 0};
  std::array<double, 9> second{};
};
MeshVolume mesh_volume(const stl::TriangleMesh& mesh);
// The inertia tensor at unit density about the point p (row-major): tr(S_p)
// 1 - S_p, S_p = S - p m^T - m p^T + V p p^T the second moments about p
// (m = V x centroid, the first moment).
std::array<double, 9> inertia_about(const MeshVolume& v, const Vec& p);

// What goes to the fluid: per marker its position, velocity and acceleration
// at the window's start, Delta V_Gamma over the cell volume, its body and its
// outward normal; per
// body the reference point of its torque and that point's velocity and
// acceleration. Within a window the fluid moves both at constant acceleration
// (x + u s + a s^2 / 2, velocity u + a s): exact for a translation, second
// order in the window for an oscillation or a rotation, whose markers would
// otherwise be held to the window start's velocity.
struct Marker {
  Vec x{0, 0, 0}, u{0, 0, 0};
  double volume_ratio = 0.0;  // Delta V_Gamma / (dx dy dz)
  int body = 0;
  Vec a{0, 0, 0};
  Vec n{0, 0, 0};  // outward unit normal of its piece of surface (the fluid's wall distance)
  // Position and velocity a time s after the set's.
  Vec x_at(double s) const {
    return {x[0] + (u[0] + 0.5 * a[0] * s) * s, x[1] + (u[1] + 0.5 * a[1] * s) * s,
            x[2] + (u[2] + 0.5 * a[2] * s) * s};
  }
  Vec u_at(double s) const { return {u[0] + a[0] * s, u[1] + a[1] * s, u[2] + a[2] * s}; }
};
struct BodyFrame {
  Vec centre{0, 0, 0}, velocity{0, 0, 0}, acceleration{0, 0, 0};
};
struct MarkerSet {
  double time = 0.0;  // s: the time of the positions
  std::vector<BodyFrame> bodies;
  std::vector<Marker> markers;
  // Flat doubles for the message (pack) and back (unpack).
  std::vector<double> pack() const;
  static MarkerSet unpack(const std::vector<double>& flat);
};

}  // namespace coflow::ibm
