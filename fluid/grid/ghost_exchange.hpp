// Ghost exchange of cell fields on the fluid grid (any method: fv's pressure
// and velocities, a two-phase LBM's phase field): each ghost cell takes the
// value of the owned cell it stands for on the neighbouring rank, or on this
// rank one period away; ghosts beyond a wall of the domain are left to the
// method's boundary conditions. Faces, edges and corners are exchanged
// directly (26 neighbours in 3D), so corner ghosts are right after one call.
#pragma once

#include <mpi.h>

#include <span>
#include <vector>

#include "fluid/grid/block.hpp"
#include "fluid/grid/neighbours.hpp"

namespace coflow::fluid::grid {

class GhostExchange {
 public:
  // Block `rank` of `dec` with `width` ghost layers, fields of `components`
  // values per cell; collective over `comm` (the ranks of `dec`).
  GhostExchange(const coupler::Decomposition& dec, int rank, int width, int components, MPI_Comm comm);

  const Block& block() const { return block_; }
  // A field of block().cells() cells, x fastest, components innermost.
  std::size_t field_size() const { return static_cast<std::size_t>(block_.cells()) * components_; }
  // Start: send the owned cells the neighbours need, copy periodic images
  // within the block. Then finish: receive into the ghosts.
  void post(std::span<double> field);
  void finish(std::span<double> field);
  void exchange(std::span<double> field) {
    post(field);
    finish(field);
  }

 private:
  template <class F>
  void for_box(const coupler::Box& b, F&& f) const {
    for (long k = b.lo[2]; k < b.hi[2]; ++k)
      for (long j = b.lo[1]; j < b.hi[1]; ++j)
        for (long i = b.lo[0]; i < b.hi[0]; ++i) f(block_.idx(i, j, k));
  }
  Block block_;
  int components_ = 1;
  int rank_ = 0;
  MPI_Comm comm_;
  std::vector<Neighbour> links_;
  std::vector<std::vector<double>> send_, recv_;
  std::vector<MPI_Request> requests_;
};

}  // namespace coflow::fluid::grid
