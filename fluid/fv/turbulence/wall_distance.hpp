// The distance to immersed bodies for the k-epsilon model's wall distance
// (seed 003 eqs. 3.18-3.27 use the distance y to the nearest wall): the
// fluid has the bodies as markers (points about a cell apart on the surface,
// each with its outward normal and area; immersed/ibm/markers.hpp), not their
// meshes. A point's distance is that to its nearest marker's piece of
// surface, taken in the tangent plane as a disc as wide as the diagonal of
// the square of the marker's area (in 2D the segment of its length): the
// normal distance while the point lies over the disc, else the distance to
// its rim. On a surface of curvature radius R sampled about a cell h apart
// it errs by about h^2 / R (the pieces' sagitta; tests/unit/fluid/
// test_wall_distance.cpp). A marker without a normal (the pieces
// of both faces of a plate thinner than its box cancel) gives the distance
// to its point. The nearest marker is found in a k-d tree (built once per
// marker set: a few dozen lines; FCL, which the particles use, needs the
// triangles the fluid does not have).
#pragma once

#include <array>
#include <vector>

#include "immersed/ibm/markers.hpp"

namespace coflow::fluid::fv {

class BodyDistance {
 public:
  // `h`: the cell's sides, to turn the markers' Delta V_Gamma / cell volume
  // back into their areas (ibm::GridGeometry::shell). `dims` 2: distances in
  // x-y only, each marker a segment of the slab's depth h_z.
  BodyDistance(const ibm::MarkerSet& set, const std::array<double, 3>& h, int dims);
  bool empty() const { return points_.empty(); }
  // The distance from x to the bodies' surface (infinity without markers).
  double operator()(const std::array<double, 3>& x) const;

 private:
  struct Point {
    std::array<double, 3> x, n;
    double half_side;  // the disc's radius: half the diagonal of its area's square (2D: half its segment)
  };
  int build(int lo, int hi, int depth);  // the tree over points_[lo, hi): its root node
  void nearest(int node, const std::array<double, 3>& x, int& best, double& best_d2) const;
  double piece_distance(const Point& p, const std::array<double, 3>& x) const;

  struct Node {
    int point = -1, axis = 0, left = -1, right = -1;
  };
  std::vector<Point> points_;
  std::vector<Node> nodes_;
  int root_ = -1, dims_ = 3;
};

}  // namespace coflow::fluid::fv
