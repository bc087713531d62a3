// Benchmark: dense field exchange through the coupler vs plain MPI.
//
//   mpirun --oversubscribe -np 8 build/bin/bench-coupler-exchange [cells] [repeats]
//
// 1. Setup: the communication map of a 128^3 x 3 field between two components
//    of k ranks each (k x k, k = 1, 2, 4, ... up to half the ranks), built
//    from block intersections; max over ranks; and the largest resident
//    memory of a rank (VmHWM: the MPI library's share grows with the ranks).
// 2. Throughput: the same field between two 1-rank components (world ranks 0
//    and 1): FieldExchange send/receive vs MPI_Sendrecv of the same bytes, in
//    the same run. Ranks 2.. sleep meanwhile so they do not steal the cores.
// Last line: RESULT exchange_gbs=... mpi_gbs=... ratio=... setup_s=... (setup at 4 x 4)
#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_args.hpp"
#include "bench_util.hpp"
#include "coflow/exchange.hpp"
#include "coflow/trace.hpp"

using namespace coflow::coupler;

namespace {

using coflow::bench::sleepy_barrier;

// The map of a k x k split of world ranks 0 .. 2k - 1 (others: MPI_COMM_NULL);
// the time to build it, max over the ranks (0 on ranks outside).
double map_setup(int k, const Index3& cells, int nc) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm half, inter;
  const int color = rank < k ? 0 : rank < 2 * k ? 1 : MPI_UNDEFINED;
  MPI_Comm_split(MPI_COMM_WORLD, color, rank, &half);
  double setup = 0.0;
  if (half != MPI_COMM_NULL) {
    MPI_Intercomm_create(half, 0, MPI_COMM_WORLD, color == 0 ? k : 0, 11, &inter);
    const Decomposition a(cells, k), b(cells, k);
    int hr = 0;
    MPI_Comm_rank(half, &hr);
    MPI_Barrier(half);
    const double t0 = now();
    {
      FieldExchange ex(inter, color == 0 ? FieldExchange::Role::sender : FieldExchange::Role::receiver,
                       color == 0 ? a : b, hr, color == 0 ? b : a, {"velocity", nc, Transfer::consistent, 2}, 21);
      setup = now() - t0;
    }
    MPI_Comm_free(&inter);
    MPI_Comm_free(&half);
  }
  double most = 0.0;
  MPI_Reduce(&setup, &most, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  return most;
}

// Peak resident memory of this process, MiB (Linux /proc/self/status VmHWM).
double peak_mib() {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  long n = 128;
  int repeats = 20;
  CLI::App app{"bench-coupler-exchange: the coupler's field exchange (see bench/coupler_exchange.cpp)"};
  app.add_option("cells", n,
                 "cells along each axis of the cube (3 n^3 doubles: one MPI message, so at most 800)")
      ->check(CLI::Range(2L, 800L))
      ->capture_default_str();
  app.add_option("repeats", repeats, "timed exchanges")
      ->check(CLI::Range(1, 100000000))
      ->capture_default_str();
  coflow::bench::parse_args(app, argc, argv);
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size < 2) {  // the throughput needs two components
    if (rank == 0)
      std::fprintf(stderr, "bench-coupler-exchange: needs at least 2 ranks (mpirun -np 8 ...)\n");
    MPI_Finalize();
    return 2;
  }
  const Index3 cells{n, n, n};
  const int nc = 3;

  // --- 1. map setup at k x k, and the memory of a rank ---
  double setup = 0.0;
  for (int k = 1; 2 * k <= size; k *= 2) {
    const double t = map_setup(k, cells, nc);
    if (k == 4) setup = t;
    if (rank == 0) std::printf("communication map setup at %d x %d ranks: %.4f s (max over ranks)\n", k, k, t);
  }
  double mine = peak_mib(), most = 0.0;
  MPI_Reduce(&mine, &most, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  if (rank == 0) std::printf("peak resident memory of a rank: %.1f MiB (largest of %d ranks)\n", most, size);

  // --- 2. throughput at 1 x 1 ---
  MPI_Comm pair = MPI_COMM_NULL, one = MPI_COMM_NULL, inter = MPI_COMM_NULL;
  MPI_Comm_split(MPI_COMM_WORLD, rank < 2 ? 0 : MPI_UNDEFINED, rank, &pair);
  double t_ex = 0, t_mpi = 0;
  const double bytes = static_cast<double>(n * n * n * nc) * sizeof(double);
  if (pair != MPI_COMM_NULL) {
    MPI_Comm_split(pair, rank, 0, &one);
    MPI_Intercomm_create(one, 0, pair, 1 - rank, 12, &inter);
    const Decomposition d(cells, 1);
    FieldExchange ex(inter, rank == 0 ? FieldExchange::Role::sender : FieldExchange::Role::receiver, d, 0, d,
                     {"velocity", nc, Transfer::consistent, 0}, 31);
    std::vector<double> field(ex.local_size());
    for (std::size_t i = 0; i < field.size(); ++i) field[i] = 1e-3 * static_cast<double>(i % 1000);
    std::vector<double> other(field.size()), plain(field.size());  // the exchange's and MPI's copies
    for (int r = -2; r < repeats; ++r) {  // two warm-up rounds
      MPI_Barrier(pair);
      double t0 = now();
      if (rank == 0) {
        ex.send(field);
        ex.flush();
      } else {
        ex.receive(other);
      }
      MPI_Barrier(pair);
      if (r >= 0) t_ex += now() - t0;
      t0 = now();
      const int count = static_cast<int>(field.size());
      if (rank == 0)
        MPI_Sendrecv(field.data(), count, MPI_DOUBLE, 1, 41, nullptr, 0, MPI_DOUBLE, 1, 42, pair, MPI_STATUS_IGNORE);
      else
        MPI_Sendrecv(nullptr, 0, MPI_DOUBLE, 0, 42, plain.data(), count, MPI_DOUBLE, 0, 41, pair,
                     MPI_STATUS_IGNORE);
      MPI_Barrier(pair);
      if (r >= 0) t_mpi += now() - t0;
    }
    if (rank == 1 && (other != field || plain != field)) std::printf("ERROR: wrong data received\n");
  }
  sleepy_barrier(MPI_COMM_WORLD);
  if (rank == 0) {
    const double ex_gbs = bytes * repeats / t_ex / 1e9, mpi_gbs = bytes * repeats / t_mpi / 1e9;
    std::printf("field: %ld^3 cells x %d doubles = %.1f MB per exchange, %d repeats\n", n, nc, bytes / 1e6, repeats);
    std::printf("coupler FieldExchange (1 x 1): %.3f s per exchange, %.2f GB/s\n", t_ex / repeats, ex_gbs);
    std::printf("plain MPI_Sendrecv (same bytes): %.3f s per exchange, %.2f GB/s\n", t_mpi / repeats, mpi_gbs);
    if (size < 8) std::printf("(the 4 x 4 map setup needs 8 ranks: setup_s is 0)\n");
    std::printf("RESULT exchange_gbs=%.3f mpi_gbs=%.3f ratio=%.3f setup_s=%.4f\n", ex_gbs, mpi_gbs, ex_gbs / mpi_gbs,
                setup);
  }
  if (inter != MPI_COMM_NULL) MPI_Comm_free(&inter);
  MPI_Finalize();
  return 0;
}
