#include "fluid/fv/amr/uniform_view.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "coflow/mpi_count.hpp"

namespace coflow::fluid::fv::amr {

namespace {

// `counts` times `scale`, and their displacements (into displs).
// MPI's counts and displacements are int: past 2^31 - 1 values (a rank's box
// of 7e8 cells, 3 values each) they would wrap; coupler::mpi_count throws.
std::vector<int> scaled(const std::vector<int>& counts, int scale, std::vector<int>& displs) {
  std::vector<int> out(counts.size());
  displs.assign(counts.size(), 0);
  std::size_t at = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    displs[r] = coupler::mpi_count(at, "refinement: the uniform view's values (displacement)");
    out[r] = coupler::mpi_count(static_cast<std::size_t>(counts[r]) * static_cast<std::size_t>(scale),
                                "refinement: the uniform view's values");
    at += static_cast<std::size_t>(out[r]);
  }
  return out;
}

std::vector<int> offsets(const std::vector<int>& counts) {
  std::vector<int> d(counts.size(), 0);
  std::size_t at = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    d[r] = coupler::mpi_count(at, "refinement: the uniform view's cells (displacement)");
    at += static_cast<std::size_t>(counts[r]);
  }
  return d;
}

}  // namespace

UniformView::UniformView(const CompositeGrid& grid, const coupler::Decomposition& dec, int rank)
    : comm_(grid.forest().comm()), local_cells_(grid.local_cells()), owned_cells_(dec.block(rank).volume()) {
  const int finest = grid.forest().spec().max_level, dims = grid.dims();
  for (int a = 0; a < dims; ++a)
    if (grid.extent(finest, a) != dec.cells()[static_cast<std::size_t>(a)])
      throw std::invalid_argument(fmt::format("refinement: the finest level has {} cells along axis {}, the fluid "
                                              "grid {}",
                                              grid.extent(finest, a), a, dec.cells()[static_cast<std::size_t>(a)]));
  const auto ranks = static_cast<std::size_t>(dec.ranks());
  // Each leaf cell's fine cells, with the rank owning each and its index there.
  std::vector<std::vector<std::pair<long, long>>> to(ranks);  // (leaf cell, index in the owner's box)
  weight_.resize(static_cast<std::size_t>(local_cells_));
  for (long c = 0; c < local_cells_; ++c) {
    const auto cell = grid.local_cell(c);
    const long r = 1L << (finest - cell.level);
    const long rz = dims == 3 ? r : 1;
    weight_[static_cast<std::size_t>(c)] = 1.0 / static_cast<double>(r * r * rz);
    for (long k = 0; k < rz; ++k)
      for (long j = 0; j < r; ++j)
        for (long i = 0; i < r; ++i) {
          const coupler::Index3 f{cell.index[0] * r + i, cell.index[1] * r + j, cell.index[2] * rz + k};
          const int owner = dec.owner(f);
          const coupler::Box& b = dec.block(owner);
          const long at = ((f[2] - b.lo[2]) * b.extent(1) + (f[1] - b.lo[1])) * b.extent(0) + (f[0] - b.lo[0]);
          to[static_cast<std::size_t>(owner)].emplace_back(c, at);
        }
  }
  send_counts_.resize(ranks);
  std::vector<long> send_at;
  for (std::size_t q = 0; q < ranks; ++q) {
    send_counts_[q] = coupler::mpi_count(to[q].size(), "refinement: the uniform view's cells");
    for (const auto& [c, at] : to[q]) {
      send_cell_.push_back(c);
      send_at.push_back(at);
    }
  }
  recv_counts_.resize(ranks);
  MPI_Alltoall(send_counts_.data(), 1, MPI_INT, recv_counts_.data(), 1, MPI_INT, comm_);
  send_displs_ = offsets(send_counts_);
  recv_displs_ = offsets(recv_counts_);
  recv_fine_.resize(static_cast<std::size_t>(recv_displs_.back() + recv_counts_.back()));
  MPI_Alltoallv(send_at.data(), send_counts_.data(), send_displs_.data(), MPI_LONG, recv_fine_.data(),
                recv_counts_.data(), recv_displs_.data(), MPI_LONG, comm_);
  int wrong = static_cast<long>(recv_fine_.size()) != owned_cells_;  // every rank learns it: no hang
  MPI_Allreduce(MPI_IN_PLACE, &wrong, 1, MPI_INT, MPI_MAX, comm_);
  if (wrong) throw std::logic_error("refinement: the uniform view does not cover the owned boxes once");
}

void UniformView::to_uniform(std::span<const double> cells, int n, std::vector<double>& out) const {
  const auto N = static_cast<std::size_t>(n);
  send_.resize(send_cell_.size() * N);
  recv_.resize(recv_fine_.size() * N);
  for (std::size_t s = 0; s < send_cell_.size(); ++s)
    for (std::size_t q = 0; q < N; ++q) send_[s * N + q] = cells[static_cast<std::size_t>(send_cell_[s]) * N + q];
  sc_ = scaled(send_counts_, n, sd_);
  rc_ = scaled(recv_counts_, n, rd_);
  MPI_Alltoallv(send_.data(), sc_.data(), sd_.data(), MPI_DOUBLE, recv_.data(), rc_.data(), rd_.data(), MPI_DOUBLE,
                comm_);
  out.assign(static_cast<std::size_t>(owned_cells_) * N, 0.0);
  for (std::size_t s = 0; s < recv_fine_.size(); ++s)
    for (std::size_t q = 0; q < N; ++q) out[static_cast<std::size_t>(recv_fine_[s]) * N + q] = recv_[s * N + q];
}

void UniformView::to_cells(std::span<const double> fine, int n, std::vector<double>& out) const {
  const auto N = static_cast<std::size_t>(n);
  send_.resize(recv_fine_.size() * N);
  recv_.resize(send_cell_.size() * N);
  for (std::size_t s = 0; s < recv_fine_.size(); ++s)
    for (std::size_t q = 0; q < N; ++q) send_[s * N + q] = fine[static_cast<std::size_t>(recv_fine_[s]) * N + q];
  sc_ = scaled(recv_counts_, n, sd_);
  rc_ = scaled(send_counts_, n, rd_);
  MPI_Alltoallv(send_.data(), sc_.data(), sd_.data(), MPI_DOUBLE, recv_.data(), rc_.data(), rd_.data(), MPI_DOUBLE,
                comm_);
  out.assign(static_cast<std::size_t>(local_cells_) * N, 0.0);
  for (std::size_t s = 0; s < send_cell_.size(); ++s) {
    const auto c = static_cast<std::size_t>(send_cell_[s]);
    for (std::size_t q = 0; q < N; ++q) out[c * N + q] += recv_[s * N + q] * weight_[c];
  }
}

}  // namespace coflow::fluid::fv::amr
