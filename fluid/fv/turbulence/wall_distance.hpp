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
// to its point. Markers retracted into the body (immersed.ibm.retraction)
// are put back on the surface along their normals. On a periodic axis the
// markers are wrapped into the box and the point's images are searched too.
// The nearest marker is found in a k-d tree (built once per marker set: a few
// dozen lines; FCL, which the particles use, needs the triangles the fluid
// does not have).
#pragma once

#include <array>
#include <vector>

#include "coflow/run_config.hpp"
#include "immersed/ibm/markers.hpp"

namespace coflow::fluid::fv {

class BodyDistance {
 public:
  // The grid: `h` the cell's sides, to turn the markers' Delta V_Gamma / cell
  // volume back into their areas (ibm::GridGeometry::shell); `dims` 2:
  // distances in x-y only, each marker a segment of the slab's depth h_z; the
  // box and its periodic axes; `retraction` in cells, as immersed.ibm's.
  struct Grid {
    std::array<double, 3> h{1, 1, 1}, lower{0, 0, 0}, upper{1, 1, 1};
    std::array<bool, 3> periodic{false, false, false};
    int dims = 3;
    double retraction = 0.0;
  };
  BodyDistance(const ibm::MarkerSet& set, const Grid& grid);
  // The grid of a run: its domain and immersed.ibm.retraction.
  static Grid grid_of(const config::Config& cfg);
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
  double nearest_distance(const std::array<double, 3>& x) const;

  struct Node {
    int point = -1, axis = 0, left = -1, right = -1;
  };
  std::vector<Point> points_;
  std::vector<Node> nodes_;
  int root_ = -1, dims_ = 3;
  Grid grid_;
};

}  // namespace coflow::fluid::fv
