#include "particles/dem/mesh.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fcl/fcl.h>
#include <fmt/format.h>

namespace coflow::particles::dem {

V3 closest_on_triangle(const V3& p, const V3& a, const V3& b, const V3& c, bool& face) {
  face = false;
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const V3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const V3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  face = true;
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

struct MeshWall::Fcl {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> model;
  std::unique_ptr<fcl::CollisionObjectd> object;
  // The triangles whose bounding volumes and shapes meet `shape` placed at tf.
  void query(const std::shared_ptr<fcl::CollisionGeometryd>& shape, const fcl::Transform3d& tf,
             std::vector<int>& triangles) const {
    fcl::CollisionObjectd s(shape, tf);
    s.computeAABB();
    fcl::CollisionRequestd request(static_cast<std::size_t>(model->num_tris), false);
    fcl::CollisionResultd result;
    fcl::collide(object.get(), &s, request, result);
    std::vector<fcl::Contactd> found;
    result.getContacts(found);
    triangles.clear();
    for (const auto& c : found) triangles.push_back(static_cast<int>(c.b1));
  }
};

MeshWall::MeshWall(TriangleMesh mesh, double friction) : mesh_(std::move(mesh)), friction_(friction) {
  fcl_ = std::make_shared<Fcl>();
  fcl_->model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> v(mesh_.vertices.begin(), mesh_.vertices.end());
  std::vector<fcl::Triangle> t;
  for (const auto& tr : mesh_.triangles) t.emplace_back(tr[0], tr[1], tr[2]);
  fcl_->model->beginModel(static_cast<int>(t.size()), static_cast<int>(v.size()));
  fcl_->model->addSubModel(v, t);
  fcl_->model->endModel();
  fcl_->object = std::make_unique<fcl::CollisionObjectd>(fcl_->model);
  fcl_->object->computeAABB();
  lo_ = hi_ = mesh_.vertices.front();
  for (const V3& p : mesh_.vertices) {
    lo_ = lo_.cwiseMin(p);
    hi_ = hi_.cwiseMax(p);
  }
}

void MeshWall::contacts(const V3& x, double r, std::vector<MeshContact>& out) const {
  out.clear();
  // Broad phase: the triangles whose bounding volumes and shapes meet a slightly
  // larger sphere; the exact test follows.
  // (inflated: FCL's GJK tolerance would miss contacts of tiny overlap)
  std::vector<int> hits;
  fcl_->query(std::make_shared<fcl::Sphered>(r * 1.05), fcl::Transform3d(Eigen::Translation3d(x)), hits);
  for (const int t : hits) {
    const auto& tr = mesh_.triangles[t];
    MeshContact m;
    m.triangle = t;
    m.point = closest_on_triangle(x, mesh_.vertices[tr[0]], mesh_.vertices[tr[1]], mesh_.vertices[tr[2]], m.face);
    out.push_back(m);
  }
  finish(x, r, out);
}

void MeshWall::swept_candidates(const V3& x0, const V3& x1, double r, std::vector<int>& out) const {
  out.clear();
  // Nothing to find unless the swept sphere's box meets the mesh's box.
  const double reach = 1.05 * r + 1e-12;
  for (int k = 0; k < 3; ++k)
    if (std::min(x0[k], x1[k]) - reach > hi_[k] || std::max(x0[k], x1[k]) + reach < lo_[k]) return;
  // A capsule along the segment (FCL's capsules lie along z, centred), inflated
  // a little as in contacts().
  const V3 d = x1 - x0;
  const double len = d.norm();
  const double rr = r * 1.05 + 1e-12;
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = 0.5 * (x0 + x1);
  if (len > 0.0) tf.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), d / len).toRotationMatrix();
  std::shared_ptr<fcl::CollisionGeometryd> shape;
  if (len > 0.0)
    shape = std::make_shared<fcl::Capsuled>(rr, len);
  else
    shape = std::make_shared<fcl::Sphered>(rr);
  fcl_->query(shape, tf, out);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

void MeshWall::contacts_all(const V3& x, double r, std::vector<MeshContact>& out) const {
  out.clear();
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const auto& tr = mesh_.triangles[t];
    MeshContact m;
    m.triangle = static_cast<int>(t);
    m.point = closest_on_triangle(x, mesh_.vertices[tr[0]], mesh_.vertices[tr[1]], mesh_.vertices[tr[2]], m.face);
    out.push_back(m);
  }
  finish(x, r, out);
}

// The contacts are the closest points that are local minima of the distance
// over the whole surface. A point inside a face always is. A point on an edge
// or a vertex is one only where every triangle that holds it has its own
// closest point there too: where one of them comes closer elsewhere (a
// coplanar or concave neighbour, the other triangle of a face cut in two),
// that neighbour's point is the contact. Every triangle holding such a point
// is within r of the centre, so among the candidates. One contact per
// distinct point. "Holds" and "there" are within 1e-6 r: the two triangles of
// an edge compute its points from opposite ends (last bits apart), and a
// vertex of a mesh not conforming at a seam (a T-junction) sits a float's
// rounding off its neighbour's edge.
void MeshWall::finish(const V3& x, double r, std::vector<MeshContact>& out) const {
  std::erase_if(out,
                [&](const MeshContact& m) { return !((x - m.point).norm() < r); });  // NaN too (a sliver)
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.triangle < b.triangle; });
  const double tol = 1e-6 * r;
  const auto holds = [&](const MeshContact& other, const V3& q) {  // q on other's triangle
    const auto& t = mesh_.triangles[static_cast<std::size_t>(other.triangle)];
    bool face = false;
    const V3 c =
        closest_on_triangle(q, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]], face);
    return (c - q).norm() <= tol;
  };
  std::vector<MeshContact> kept;
  for (const auto& m : out) {
    const bool minimum = m.face || std::none_of(out.begin(), out.end(), [&](const MeshContact& o) {
                           return (o.point - m.point).norm() > tol && holds(o, m.point);
                         });
    const bool dup = std::any_of(kept.begin(), kept.end(),
                                 [&](const auto& k) { return (k.point - m.point).norm() <= tol; });
    if (minimum && !dup) kept.push_back(m);
  }
  out.swap(kept);
}

}  // namespace coflow::particles::dem
