// Triangle-mesh walls: STL files (ASCII or binary), FCL's bounding-volume
// hierarchy as the broad phase, exact closest points for the contacts.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "particles/dem/contact.hpp"
#include "particles/dem/stl.hpp"

namespace coflow::particles::dem {

struct MeshContact {
  int triangle = 0;
  V3 point = V3::Zero();  // closest point of the triangle to the sphere centre
  bool face = false;      // inside the face (not on an edge or a vertex)
};

class MeshWall {
 public:
  MeshWall(TriangleMesh mesh, double friction);
  double friction() const { return friction_; }
  std::size_t size() const { return mesh_.triangles.size(); }
  // The triangles a sphere (centre x, radius r) touches, sorted by triangle:
  // the closest points that are local minima of the distance over the mesh
  // (a point inside a face; an edge or a vertex point only where every
  // triangle holding it is closest there: a convex rim), one per distinct
  // point, so a flat mesh acts like one plane whichever triangles it is cut
  // into, and a sphere on a floor still meets a post's edge.
  void contacts(const V3& x, double r, std::vector<MeshContact>& out) const;      // FCL broad phase
  void contacts_all(const V3& x, double r, std::vector<MeshContact>& out) const;  // every triangle (oracle)
  // The triangles that a sphere of radius r moving from x0 to x1 may touch
  // (FCL's BVH against the capsule the sphere sweeps; a superset), sorted.
  void swept_candidates(const V3& x0, const V3& x1, double r, std::vector<int>& out) const;
  const V3& vertex(int triangle, int corner) const { return mesh_.vertices[mesh_.triangles[triangle][corner]]; }

 private:
  void finish(const V3& x, double r, std::vector<MeshContact>& out) const;
  TriangleMesh mesh_;
  V3 lo_, hi_;  // bounding box of the mesh
  double friction_;
  struct Fcl;
  std::shared_ptr<Fcl> fcl_;
};

// Mesh-wall contact histories are kept per direction, not per triangle: a
// contact sliding from one triangle to a coplanar neighbour keeps its shear
// spring; a sphere in a corner has one history per face. Returns the slot of
// the history whose normal matches n (or a free one), among `slots` per mesh.
// A history without a direction (from a checkpoint written before they were
// saved) is taken by the first contact that looks for one.
inline constexpr int kMeshSlots = 16;
template <class Lookup>
int mesh_history_slot(const V3& n, long step, Lookup&& state_of_slot) {
  int free_slot = -1;
  for (int k = 0; k < kMeshSlots; ++k) {
    const ContactState* st = state_of_slot(k);
    if (!st) {
      if (free_slot < 0) free_slot = k;
      continue;
    }
    if (st->seen != step && (st->normal.dot(n) > 0.99 || st->normal.squaredNorm() == 0.0)) return k;
  }
  return free_slot < 0 ? 0 : free_slot;
}

// Closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision
// Detection, 5.1.5); `face` tells whether it lies inside the triangle.
V3 closest_on_triangle(const V3& p, const V3& a, const V3& b, const V3& c, bool& face);

}  // namespace coflow::particles::dem
