// Every rank's items concatenated, in rank order: on rank 0 of a communicator
// (gather_to_root) or on every rank (allgather).
#pragma once

#include <mpi.h>

#include <span>
#include <vector>

#include "coflow/mpi_count.hpp"

namespace coflow::coupler {

// Collective. Every rank's count n on every rank (counts) and where each
// rank's items start (offsets); the total, checked against the MPI count
// limit on every rank, so that all refuse an oversized gather together.
inline long gather_counts(MPI_Comm comm, int n, std::vector<int>& counts, std::vector<int>& offsets,
                          const char* what) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  counts.assign(static_cast<std::size_t>(size), 0);
  offsets.assign(static_cast<std::size_t>(size), 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  long total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    offsets[r] = static_cast<int>(total);
    total += counts[r];
  }
  mpi_count(static_cast<std::size_t>(total), what);
  return total;
}

// Collective. On rank 0 returns all items and, if asked, each rank's count and
// offset; elsewhere returns nothing. `type` is the MPI type of T.
template <class T>
std::vector<T> gather_to_root(MPI_Comm comm, std::span<const T> local, MPI_Datatype type,
                              std::vector<int>* counts = nullptr, std::vector<int>* offsets = nullptr) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const int n = mpi_count(local.size(), "gather to rank 0 (items of one rank)");
  std::vector<int> c, o;
  const long total = gather_counts(comm, n, c, o, "gather to rank 0 (items)");
  std::vector<T> all(rank == 0 ? static_cast<std::size_t>(total) : 0);
  if (rank != 0) c.clear(), o.clear();
  MPI_Gatherv(local.data(), n, type, all.data(), c.data(), o.data(), type, 0, comm);
  if (counts) *counts = c;
  if (offsets) *offsets = o;
  return all;
}

// Collective. Every rank receives all items, in rank order.
template <class T>
std::vector<T> allgather(MPI_Comm comm, std::span<const T> local, MPI_Datatype type) {
  const int n = mpi_count(local.size(), "gather to every rank (items of one rank)");
  std::vector<int> c, o;
  const long total = gather_counts(comm, n, c, o, "gather to every rank (items)");
  std::vector<T> all(static_cast<std::size_t>(total));
  MPI_Allgatherv(local.data(), n, type, all.data(), c.data(), o.data(), type, comm);
  return all;
}

}  // namespace coflow::coupler
