// Fluid probes (run.output.probes, run.output.pressure_drops) into
// series/probes.csv: velocity and pressure at points and along lines,
// trilinear between cell centres (clamped to the outermost centres next to a
// wall), and the fluid's mean pressure over two planes (cells weighted by
// their fluid fraction: interior solids do not count) with their difference. The
// rank owning a sample's stencil corner interpolates it from its cells and one
// ghost layer (grid::GhostExchange); rank 0 gets every value.
#pragma once

#include <mpi.h>

#include <memory>
#include <string>
#include <vector>

#include "coflow/config.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/grid/ghost_exchange.hpp"

namespace coflow::fluid {

class Probes {
 public:
  Probes(const config::Config& cfg, const coupler::Decomposition& dec, int rank, MPI_Comm comm);
  bool empty() const { return samples_.empty() && drops_.empty(); }
  // The columns after time.
  const std::vector<std::string>& columns() const { return columns_; }
  // Collective: one row's values (on rank 0; zeros elsewhere).
  std::vector<double> sample(FluidSolver& solver);

 private:
  struct Stencil {
    int owner = -1;        // rank that interpolates
    long corner[3] = {0, 0, 0};  // owned-relative cell of the lower corner (on the owner)
    double t[3] = {0, 0, 0};     // weights of the upper cells
  };
  struct Drop {
    int axis = 0;
    long cell[2][2] = {{0, 0}, {0, 0}};  // per plane: the two cell layers
    double t[2] = {0, 0};                // per plane: weight of the upper layer
  };
  Stencil stencil(const config::Vec3& x) const;
  Drop drop(const config::PressureDropParams& p) const;
  void interpolate(const Stencil& s, double* out) const;  // ux, uy, uz, p
  void plane_sums(const Drop& d, const double* p, const double* solid, double* sum, double* fluid) const;

  const config::Config& cfg_;
  coupler::Decomposition dec_;
  int rank_ = 0;
  MPI_Comm comm_;
  std::vector<Stencil> samples_;
  std::vector<Drop> drops_;
  std::vector<std::string> columns_;
  std::unique_ptr<grid::GhostExchange> ghosts_;  // velocity and pressure: 4 per cell
  std::vector<double> field_;
};

}  // namespace coflow::fluid
