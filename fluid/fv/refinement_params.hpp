// fluid.fv.refinement: fv on the block-structured adaptive grid (seed 003
// §4.1.1; fluid/fv/amr). domain.cells is the grid of the finest level, the
// uniform grid the adaptive one stands in for: the coupled components
// exchange on it, and snapshots and probes read it (each fine cell shows the
// value of the leaf cell that holds it); the composite grid's own levels go
// to a second file per snapshot (*_levels.xmf).
#pragma once

#include <string>
#include <vector>

#include "coflow/config.hpp"
#include "coflow/run_config.hpp"

namespace coflow::fluid::fv {

// One refinement criterion (a leaf refines where any criterion asks, and
// coarsens where all allow).
struct RefinementCriterion {
  std::string kind;  // vorticity | walls | box | bodies | particles
  double refine_above = 0.0, coarsen_below = 0.0;  // vorticity: 1/s
  double distance = 0.0;                           // walls: m
  config::Numbers lower, upper;                    // box: m
};

struct RefinementParams {
  bool on = false;  // the section is given
  int levels = 2;
  int patch = 8;
  int every = 10;
  std::string diffusion = "explicit";  // or implicit (CompositeFlow::set_implicit_diffusion)
  std::vector<RefinementCriterion> criteria;
  void visit(config::Visitor& v);
  // Whole-configuration checks: the grid cuts into patches, the cells are
  // cubes (keys reported as refinement.*, from fluid.fv). The variant and
  // coupling checks are fluid/schema.cpp's.
  void check(config::Visitor& v, const config::Config& cfg) const;
  // Cells per patch edge on the base level, per axis: domain.cells / 2^(levels-1).
  long base_cells(const config::Config& cfg, int axis) const;
};

}  // namespace coflow::fluid::fv
