// The composite grid seen as the uniform grid of its finest level, cut into
// the blocks of the coupler's decomposition: what the other components
// exchange with the fluid on, and what snapshots and probes read. The forest
// is partitioned by p4est (Morton order), the uniform grid by boxes, so a
// rank's leaves and its box do not coincide: each direction is one
// all-to-all.
//
// To the uniform grid, each fine cell takes the value of the leaf cell that
// holds it (piecewise constant: no new extrema, and a field constant on a
// leaf cell stays so). Back, a field given on the fine cells becomes, on each
// leaf cell, the mean over the fine cells it holds: the volume integral
// sum V f is kept exactly (a momentum source stays conservative, seed 003
// eq. 3.43), and the source lands in the finest cell that contains it.
#pragma once

#include <mpi.h>

#include <span>
#include <vector>

#include "coflow/decomposition.hpp"
#include "fluid/fv/amr/composite_grid.hpp"

namespace coflow::fluid::fv::amr {

class UniformView {
 public:
  // `decomposition` cuts the cells of the forest's finest level (max_level)
  // over the brick; this rank owns block(rank). Collective. Valid while the
  // forest does not adapt.
  UniformView(const CompositeGrid& grid, const coupler::Decomposition& decomposition, int rank);

  // `n` values per local leaf cell -> `n` values per cell of the owned box
  // (x fastest). Collective.
  void to_uniform(std::span<const double> cells, int n, std::vector<double>& out) const;
  // `n` values per cell of the owned box -> per local leaf cell, the mean over
  // the fine cells it holds. Collective.
  void to_cells(std::span<const double> fine, int n, std::vector<double>& out) const;

 private:
  MPI_Comm comm_;
  long local_cells_ = 0, owned_cells_ = 0;
  // In fine cells, per rank: what goes to (send) and comes from (recv) it.
  std::vector<int> send_counts_, send_displs_, recv_counts_, recv_displs_;
  std::vector<long> send_cell_;  // per fine cell sent: the local leaf cell holding it
  std::vector<long> recv_fine_;  // per fine cell received: its index in the owned box
  std::vector<double> weight_;   // per local leaf cell: 1 / (fine cells it holds)
  mutable std::vector<double> send_, recv_;          // message buffers, kept between calls
  mutable std::vector<int> sc_, sd_, rc_, rd_;       // their counts and displacements
};

}  // namespace coflow::fluid::fv::amr
