// The fluid grid's ghost exchange of cell fields: after one exchange every
// ghost holds the value of the owned cell it stands for (periodic images
// wrapped), corners and edges included, and ghosts beyond a wall are left
// untouched. Runs on any rank count: `unit` runs it on 1 rank (periodic
// copies within the block), `unit.mpi_4_ranks` on 4 (messages between ranks).
#include <catch2/catch.hpp>

#include <mpi.h>

#include <cmath>

#include "fluid/grid/ghost_exchange.hpp"

using coflow::coupler::Decomposition;
using coflow::coupler::Index3;
using coflow::fluid::grid::GhostExchange;

namespace {
double value(const Index3& g, int q) { return 1.0 + g[0] + 100.0 * g[1] + 10000.0 * g[2] + 0.25 * q; }
constexpr double kUntouched = -7.0;

// Fills the owned cells, exchanges, returns the number of wrong ghost values.
long wrong_ghosts(const Index3& cells, std::array<bool, 3> periodic, int width, int components) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Decomposition dec(cells, size, {0, 0, 0}, periodic);
  GhostExchange ex(dec, rank, width, components, MPI_COMM_WORLD);
  const auto& b = ex.block();
  std::vector<double> f(ex.field_size(), kUntouched);
  for (long k = 0; k < b.extent[2]; ++k)
    for (long j = 0; j < b.extent[1]; ++j)
      for (long i = 0; i < b.extent[0]; ++i)
        for (int q = 0; q < components; ++q)
          f[b.idx(i, j, k) * components + q] = value({b.owned.lo[0] + i, b.owned.lo[1] + j, b.owned.lo[2] + k}, q);
  ex.exchange(f);
  long wrong = 0;
  for (long k = -b.ghost[2]; k < b.extent[2] + b.ghost[2]; ++k)
    for (long j = -b.ghost[1]; j < b.extent[1] + b.ghost[1]; ++j)
      for (long i = -b.ghost[0]; i < b.extent[0] + b.ghost[0]; ++i) {
        const Index3 g{b.owned.lo[0] + i, b.owned.lo[1] + j, b.owned.lo[2] + k};
        bool inside = true;
        for (int d = 0; d < 3; ++d) inside = inside && (periodic[d] || (g[d] >= 0 && g[d] < cells[d]));
        const Index3 w = dec.wrap(g);
        for (int q = 0; q < components; ++q) {
          const double want = inside ? value(w, q) : kUntouched;
          const double got = f[b.idx(i, j, k) * components + q];
          if (!(got == want)) ++wrong;  // NaN counts as wrong
        }
      }
  long total = wrong;
  MPI_Allreduce(&wrong, &total, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  return total;
}
}  // namespace

TEST_CASE("ghost cells of a cell field hold their owners' values", "[fluid][mpi]") {
  REQUIRE(wrong_ghosts({12, 9, 7}, {false, false, false}, 1, 1) == 0);
  REQUIRE(wrong_ghosts({12, 9, 7}, {true, true, true}, 1, 3) == 0);
  REQUIRE(wrong_ghosts({12, 10, 8}, {true, false, true}, 2, 2) == 0);
  REQUIRE(wrong_ghosts({16, 12, 1}, {true, false, false}, 2, 1) == 0);  // 2D: no ghosts along z
}

TEST_CASE("a block thinner than its ghost layers is refused", "[fluid][mpi]") {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Decomposition dec({2, 8, 8}, size, {1, 0, 0}, {true, false, false});
  REQUIRE_THROWS_WITH(GhostExchange(dec, 0, 3, 1, MPI_COMM_WORLD), Catch::Contains("fewer than the 3 ghost layers"));
}
