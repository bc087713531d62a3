// Where the lattice links of fluid.solids' surfaces cross them: the fraction
// of a link from a fluid cell's centre to a solid cell's centre at which it
// enters a solid, the q of the interpolated bounce-back of Bouzidi, Firdaouss
// & Lallemand (2001) and of Ginzburg et al.'s (2008) central linear
// interpolation (fluid.lbm.bounce_back: interpolated, central). Spheres (discs in
// 2D) and boxes exactly, meshes by their triangles, voxel images at the
// half (their voxels' faces). Part of the fluid schema library.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "coflow/run_config.hpp"
#include "coflow/stl.hpp"
#include "fluid/two_phase_params.hpp"

namespace coflow::fluid {

class SolidSurface {
 public:
  // Throws std::runtime_error when a mesh cannot be read.
  SolidSurface(const config::Config& cfg, const std::vector<SolidParams>& solids);

  // The fraction in [0, 1] of the link from the centre of fluid cell `cell`
  // (global indices) along lattice vector e to the next cell's centre, which
  // holds solid `id` (1 + its index in fluid.solids, as solid_map), at which
  // the link first enters a solid. Across a periodic face the link is taken
  // at the solid cell's image inside the box. 0.5 where no crossing is found
  // (a voxel image, or a link that grazes a mesh's edge).
  double fraction(const std::array<long, 3>& cell, const int* e, int id) const;

 private:
  // First entry of the segment a + t (b - a), t in [0, 1], into solid n; 2 if none.
  double entry(std::size_t n, const stl::V3& a, const stl::V3& b) const;
  double mesh_entry(std::size_t m, const stl::V3& a, const stl::V3& b) const;
  long bin(const stl::V3& x) const;  // the global cell holding x (-1 outside the box)

  config::DomainParams domain_;
  std::array<double, 3> h_{};
  std::vector<SolidParams> solids_;
  std::vector<int> mesh_of_;  // per solid: its index in meshes_, or -1
  std::vector<stl::TriangleMesh> meshes_;
  // Per mesh: the triangles whose bounding box reaches each cell (by global index).
  std::vector<std::unordered_map<long, std::vector<int>>> bins_;
};

}  // namespace coflow::fluid
