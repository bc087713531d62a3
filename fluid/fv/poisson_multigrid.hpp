// fv's pressure Poisson on a uniform grid (the 5- or 7-point Laplacian of
// set_poisson: zero normal gradient at walls and velocity faces, phi given at
// open faces) by conjugate gradients preconditioned by a matrix-free
// geometric multigrid V-cycle: cell-centred full coarsening by 2 on every axis
// (coarse operators rediscretised), symmetric red-black Gauss-Seidel (one
// sweep down, one up), trilinear prolongation and its transpose as the
// restriction, and one PFMG V-cycle (hypre, StructSystem) on the coarsest level.
//
// Why not hypre alone: PFMG semicoarsens one axis per level and stores seven
// coefficients per cell, so a 3D V-cycle visits about twice the fine grid and
// reads 56 bytes of matrix per cell per sweep; this cycle visits 8/7 of it and
// reads no matrix (the Laplacian of a uniform grid has constant couplings).
// bench-fv's 128^3 cavity: a solve 1.91x faster, 48 % of the step against 65 %
// (docs/performance.md). It needs every rank's block even along every axis
// with more than one cell and cells of aspect ratio at most 2 (suits()); fv
// uses hypre's PCG + PFMG elsewhere.
#pragma once

#include <mpi.h>

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "coflow/decomposition.hpp"

namespace coflow::fluid::fv {

class StructSystem;

class PoissonMultigrid {
 public:
  struct Options {
    double tolerance = 1e-10;  // relative residual, 2-norm
    int max_iterations = 200;
    // Coarsenings before hypre's coarsest solve (fewer where the blocks do not
    // halve): 3 leave it 1/512 of the cells in 3D, 1/64 in 2D. The number
    // depends on the global grid alone wherever the blocks halve that often,
    // so that 1 rank and N ranks apply the same cycle.
    int max_coarsenings = 3;
    std::string name = "pressure Poisson solve";
  };
  // Block `rank` of `dec` (spacing h); open[f] for the domain's faces x-, x+,
  // y-, y+, z-, z+: phi = 0 on that face (else zero normal gradient), unless
  // the axis is periodic.
  PoissonMultigrid(const coupler::Decomposition& dec, int rank, MPI_Comm comm, const std::array<double, 3>& h,
                   const std::array<bool, 6>& open, Options opt);
  ~PoissonMultigrid();
  PoissonMultigrid(const PoissonMultigrid&) = delete;
  PoissonMultigrid& operator=(const PoissonMultigrid&) = delete;

  // Whether this multigrid suits the grid: it coarsens at least once (every
  // block even along every axis with more than one cell) and its cells are
  // nearly cubes (aspect at most 2: point smoothing loses its effect on
  // stretched cells, where PFMG's semicoarsening does not).
  static bool suits(const coupler::Decomposition& dec, const std::array<double, 3>& h);
  // Solve A x = b (owned cells, x fastest), x holding the first guess; throws
  // when the tolerance is not reached within max_iterations.
  void solve(std::span<const double> b, std::span<double> x);
  // Also stop when the residual's 2-norm is below `floor` (0: no floor).
  void set_absolute_floor(double floor) { floor_ = floor; }
  int last_iterations() const { return iterations_; }
  double last_residual() const { return residual_; }
  int levels() const { return static_cast<int>(levels_.size()); }

  struct Level;

 private:
  void cycle(std::size_t l);
  double apply(std::vector<double>& v);
  void remove_mean(std::vector<double>& v) const;
  Options opt_;
  MPI_Comm comm_;
  int dims_ = 3;
  bool singular_ = false;  // no face holds phi: phi up to a constant
  std::vector<std::unique_ptr<Level>> levels_;
  std::unique_ptr<StructSystem> coarsest_;
  std::vector<double> coarse_b_, coarse_x_;  // the coarsest level's owned cells
  std::vector<double> b_, x_, p_, ap_;       // conjugate gradients (padded as the finest level)
  int iterations_ = 0;
  double residual_ = 0.0, floor_ = 0.0;
};

}  // namespace coflow::fluid::fv
