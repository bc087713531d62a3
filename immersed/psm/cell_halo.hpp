// The covered cells' values shared among the immersed ranks: each rank sends
// the values of its owned cells that lie in another rank's ghost layer (the
// particles' coupling ghost width, periodic images included), so that the rank
// owning a particle's centre can sum all of the particle's shares itself, in
// the order it covers them: the same sums, bit for bit, on 1 immersed rank and
// on N (psm.cpp).
#pragma once

#include <mpi.h>

#include <cstddef>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "coflow/decomposition.hpp"

namespace coflow::immersed::psm {

class CellHalo {
 public:
  // `width`: the ghost layer, in cells (zero on axes one cell thick).
  CellHalo(MPI_Comm comm, const coupler::Decomposition& dec, int rank, int width);

  // Collective. `cells`: owned cells (global indices), `values`: `per_cell`
  // values each. Afterwards find() gives the values other ranks sent here.
  void exchange(std::span<const coupler::Index3> cells, std::span<const double> values, int per_cell);
  // The values received for a cell (its global index, wrapped into the
  // domain), or nullptr when no rank sent it.
  const double* find(const coupler::Index3& cell) const;
  // Whether any other rank's ghost layer reaches this rank's block.
  bool has_neighbours() const { return !reach_.empty(); }

 private:
  long linear(const coupler::Index3& c) const { return (c[2] * cells_[1] + c[1]) * cells_[0] + c[0]; }

  MPI_Comm comm_;
  int size_;
  coupler::Index3 cells_;
  std::vector<std::pair<int, coupler::Box>> reach_;  // (rank, owned cells in its ghost layer), by rank
  std::vector<std::vector<double>> out_;
  std::vector<double> in_;
  int per_cell_ = 0;
  std::unordered_map<long, std::size_t> at_;  // linear cell index -> offset of its values in in_
};

}  // namespace coflow::immersed::psm
