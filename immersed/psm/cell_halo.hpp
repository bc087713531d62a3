// The covered cells' values shared among the immersed ranks: each rank sends
// the values of its owned cells that lie in another rank's ghost layer (the
// particles' coupling ghost width, periodic images included), so that the rank
// owning a particle's centre can sum all of the particle's shares itself, in
// the order it covers them: the same sums, bit for bit, on 1 immersed rank and
// on N (psm.cpp).
#pragma once

#include <mpi.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
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
  // The values received for a cell of this rank's ghost layer (its global
  // index, wrapped or not on periodic axes), or nullptr when no rank sent it.
  const double* find(coupler::Index3 cell) const;

 private:
  long slot_index(const coupler::Index3& c) const;  // in the grown block; c inside it

  MPI_Comm comm_;
  int size_;
  coupler::Index3 cells_;
  std::array<bool, 3> periodic_;
  std::vector<coupler::Index3> shifts_;              // periodic images
  coupler::Box inner_;                               // owned cells no other rank's ghost layer reaches
  coupler::Box grown_;                               // this rank's block with its ghost layer
  std::vector<std::pair<int, coupler::Box>> reach_;  // (rank, owned cells in its ghost layer), by rank
  std::vector<std::vector<double>> out_;
  std::vector<double> in_;
  std::vector<std::int32_t> slot_;  // grown-block cell -> offset of its values in in_, or -1
  std::vector<long> filled_;        // the slots set by the last exchange
};

}  // namespace coflow::immersed::psm
