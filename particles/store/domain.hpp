// The domain layer of the particle models (dem, dpm): which rank owns a
// position (the fluid's block decomposition, mapped onto the box), the moves of
// particles to their new owners, and the ghost copies a neighbour needs for its
// contacts, all over the whole ParticleStore.
#pragma once

#include <mpi.h>

#include <array>
#include <vector>

#include "coflow/decomposition.hpp"
#include "particles/store/grid_cell.hpp"
#include "particles/store/particle_store.hpp"

namespace coflow::particles::store {

// Variable-size all-to-all of doubles: out[r] goes to rank r; what every rank
// sent here lands in `in`, in rank order.
void exchange(MPI_Comm comm, std::vector<std::vector<double>>& out, std::vector<double>& in);

class Domain {
 public:
  Domain() = default;
  Domain(const coupler::Decomposition& dec, const double lower[3], const double upper[3],
         const std::array<bool, 3>& periodic, MPI_Comm comm);

  int rank() const { return rank_; }
  int ranks() const { return size_; }
  MPI_Comm comm() const { return comm_; }
  const coupler::Decomposition& decomposition() const { return dec_; }

  // The rank whose block holds x (clamped into the box).
  int owner_of(const double* x) const;
  // The owner of every particle of `s`.
  std::vector<int> owners(const ParticleStore& s) const;
  // Whether x, or one of its periodic images, lies within `reach` of the block
  // of rank r.
  bool near_block(const double* x, int r, double reach) const;
  // Sends the particles whose owner is another rank (the attributes that
  // migrate) and returns the rows other ranks sent here; the caller removes the
  // leavers and appends the rows (its own state may travel alongside).
  std::vector<double> send_leavers(const ParticleStore& s, const std::vector<int>& owners) const;
  // Moves the leavers to their owners: send_leavers, keep, append, sort by id.
  void migrate(ParticleStore& s) const;
  // Sends copies of the particles within `reach` of another rank's block (the
  // attributes that travel with ghosts) and returns the rows received.
  std::vector<double> send_ghosts(const ParticleStore& s, double reach) const;

 private:
  double block_lo(int r, int d) const { return lower_[d] + dec_.block(r).lo[d] * cell_[d]; }
  double block_hi(int r, int d) const { return lower_[d] + dec_.block(r).hi[d] * cell_[d]; }
  coupler::Decomposition dec_;
  double lower_[3] = {0, 0, 0}, upper_[3] = {1, 1, 1}, cell_[3] = {1, 1, 1};
  std::array<bool, 3> periodic_{false, false, false};
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
};

}  // namespace coflow::particles::store
