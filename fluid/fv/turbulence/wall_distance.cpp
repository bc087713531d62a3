#include "fluid/fv/turbulence/wall_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace coflow::fluid::fv {

BodyDistance::BodyDistance(const ibm::MarkerSet& set, const Grid& grid) : dims_(grid.dims), grid_(grid) {
  const auto& h = grid.h;
  const ibm::GridGeometry g{{0, 0, 0}, {1, 1, 1}, {h[0], h[1], h[2]}, dims_};
  points_.reserve(set.markers.size());
  for (const auto& m : set.markers) {
    const double area = m.volume_ratio * g.cell_volume() / g.shell();
    Point p{m.x, m.n, dims_ == 2 ? 0.5 * area / h[2] : std::sqrt(0.5 * area)};
    if (dims_ == 2) p.x[2] = p.n[2] = 0.0;
    const double len = std::sqrt(p.n[0] * p.n[0] + p.n[1] * p.n[1] + p.n[2] * p.n[2]);
    for (auto& c : p.n) c = len > 0.5 ? c / len : 0.0;  // no normal: the point's distance
    for (int d = 0; d < dims_; ++d) {
      p.x[d] += grid.retraction * g.shell() * p.n[d];  // back on the surface
      const double L = grid.upper[d] - grid.lower[d];
      if (grid.periodic[d]) p.x[d] = grid.lower[d] + std::fmod(std::fmod(p.x[d] - grid.lower[d], L) + L, L);
    }
    points_.push_back(p);
  }
  nodes_.reserve(points_.size());
  root_ = build(0, static_cast<int>(points_.size()), 0);
}

BodyDistance::Grid BodyDistance::grid_of(const config::Config& cfg) {
  const auto& d = cfg.domain;
  Grid g;
  const auto h = d.spacing();
  for (std::size_t a = 0; a < 3; ++a) {
    g.h[a] = h[a];
    g.lower[a] = d.lower[a];
    g.upper[a] = d.upper[a];
    g.periodic[a] = d.periodic[a];
  }
  g.dims = d.two_dimensional() ? 2 : 3;
  g.retraction = config::resolved_number(cfg, {"immersed", "ibm", "retraction"}, 0.0);
  return g;
}

// Median split along the axes in turn; each node holds its median point.
int BodyDistance::build(int lo, int hi, int depth) {
  if (lo >= hi) return -1;
  const int axis = depth % dims_, mid = (lo + hi) / 2;
  std::nth_element(points_.begin() + lo, points_.begin() + mid, points_.begin() + hi,
                   [axis](const Point& a, const Point& b) { return a.x[axis] < b.x[axis]; });
  const int node = static_cast<int>(nodes_.size());
  nodes_.push_back({mid, axis, -1, -1});
  const int left = build(lo, mid, depth + 1), right = build(mid + 1, hi, depth + 1);
  nodes_[node].left = left;
  nodes_[node].right = right;
  return node;
}

void BodyDistance::nearest(int node, const std::array<double, 3>& x, int& best, double& best_d2) const {
  if (node < 0) return;
  const Node& nd = nodes_[node];
  const Point& p = points_[nd.point];
  double d2 = 0.0;
  for (int d = 0; d < dims_; ++d) d2 += (x[d] - p.x[d]) * (x[d] - p.x[d]);
  if (d2 < best_d2) best_d2 = d2, best = nd.point;
  const double off = x[nd.axis] - p.x[nd.axis];
  nearest(off < 0 ? nd.left : nd.right, x, best, best_d2);
  if (off * off < best_d2) nearest(off < 0 ? nd.right : nd.left, x, best, best_d2);
}

double BodyDistance::piece_distance(const Point& p, const std::array<double, 3>& x) const {
  double r2 = 0.0, normal = 0.0;
  for (int d = 0; d < dims_; ++d) {
    r2 += (x[d] - p.x[d]) * (x[d] - p.x[d]);
    normal += (x[d] - p.x[d]) * p.n[d];
  }
  const double n2 = normal * normal;
  if (n2 == 0.0 && p.n[0] == 0.0 && p.n[1] == 0.0 && p.n[2] == 0.0) return std::sqrt(r2);
  const double along = std::sqrt(std::max(0.0, r2 - n2)), beyond = std::max(0.0, along - p.half_side);
  return std::sqrt(n2 + beyond * beyond);
}

double BodyDistance::nearest_distance(const std::array<double, 3>& x) const {
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  nearest(root_, x, best, best_d2);
  return piece_distance(points_[static_cast<std::size_t>(best)], x);
}

// The point and, on periodic axes, its images one period away on either
// side, each searched only when the box is nearer to it than the best so far.
double BodyDistance::operator()(const std::array<double, 3>& x) const {
  if (root_ < 0) return std::numeric_limits<double>::infinity();
  double best = nearest_distance(x);
  bool any = false;  // no periodic axis: no images
  for (int d = 0; d < dims_; ++d) any = any || grid_.periodic[static_cast<std::size_t>(d)];
  if (!any) return best;
  int shifts[3] = {0, 0, 0};
  for (shifts[0] = -1; shifts[0] <= 1; ++shifts[0])
    for (shifts[1] = -1; shifts[1] <= 1; ++shifts[1])
      for (shifts[2] = -1; shifts[2] <= 1; ++shifts[2]) {
        std::array<double, 3> y = x;
        double gap2 = 0.0;  // squared distance from the image to the box
        bool image = false, valid = true;
        for (int d = 0; d < 3; ++d) {
          if (shifts[d] == 0) continue;
          valid = valid && d < dims_ && grid_.periodic[static_cast<std::size_t>(d)];
          image = true;
          y[d] += shifts[d] * (grid_.upper[d] - grid_.lower[d]);
          const double out = std::max({0.0, grid_.lower[d] - y[d], y[d] - grid_.upper[d]});
          gap2 += out * out;
        }
        if (image && valid && gap2 < best * best) best = std::min(best, nearest_distance(y));
      }
  return best;
}

}  // namespace coflow::fluid::fv
