// fv's adaptive grid seen as the uniform grid of its finest level
// (fluid/fv/amr/uniform_view.hpp): each fine cell of a rank's box shows the
// leaf cell that holds it, and a field on the fine cells returns to the leaf
// cells as their mean, keeping sum V f (the particles' momentum source). On
// the 2 ranks of unit.mpi, whose boxes and leaves do not coincide.
#include <catch2/catch.hpp>
#include <mpi.h>

#include <cmath>
#include <vector>

#include "amr_testing.hpp"
#include "fluid/fv/amr/composite_grid.hpp"
#include "fluid/fv/amr/uniform_view.hpp"

using namespace coflow::fluid::fv::amr;

namespace {

// 2 x 2 (x 2) trees of 4^d-cell patches, 3 levels: refined towards the
// corner at the origin, so all three levels meet; the finest grid is 32^d.
void check_view(int dims) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  auto spec = coflow::test::forest_2d({2, 2, dims == 3 ? 2 : 1}, {false, true, false}, 2, 4, 1);
  spec.dims = dims;
  spec.refine = [](int level, const Index3& p) { return p[0] + p[1] + p[2] < (level == 0 ? 1 : 2); };
  Forest forest(MPI_COMM_WORLD, spec);
  const CompositeGrid grid(forest, {{0.0, 0.0, 0.0}, 1.0});
  const long nz = dims == 3 ? 32 : 1;
  const coflow::coupler::Decomposition dec({32, 32, nz}, size, {0, 0, 0}, {false, true, false});
  const UniformView view(grid, dec, rank);
  const auto& box = dec.block(rank);
  const auto n = static_cast<std::size_t>(grid.local_cells());
  const double h = 1.0 / 16.0;  // the finest spacing: a tree of 1 is 4 x 2^2 cells
  const double cell_volume = dims == 3 ? h * h * h : h * h;

  // Each leaf cell's centre and spacing, sent to the fine cells.
  std::vector<double> leaf(4 * n);
  for (std::size_t c = 0; c < n; ++c) {
    const auto cell = grid.local_cell(static_cast<long>(c));
    const auto x = grid.centre(cell);
    for (std::size_t a = 0; a < 3; ++a) leaf[4 * c + a] = x[a];
    leaf[4 * c + 3] = grid.spacing(cell.level);
  }
  std::vector<double> fine;
  view.to_uniform(leaf, 4, fine);
  REQUIRE(fine.size() == 4 * static_cast<std::size_t>(box.volume()));
  long outside = 0, k = 0;
  std::vector<double> g(static_cast<std::size_t>(box.volume()));
  double fine_sum = 0.0;
  for (long kz = box.lo[2]; kz < box.hi[2]; ++kz)
    for (long j = box.lo[1]; j < box.hi[1]; ++j)
      for (long i = box.lo[0]; i < box.hi[0]; ++i, ++k) {
        const auto K = static_cast<std::size_t>(k);
        const double x[3] = {(i + 0.5) * h, (j + 0.5) * h, (kz + 0.5) * h};
        const double half = 0.5 * fine[4 * K + 3];
        for (std::size_t a = 0; a < static_cast<std::size_t>(dims); ++a)
          if (!(std::fabs(x[a] - fine[4 * K + a]) < half)) {
            ++outside;
            break;
          }
        // A varying field for the integral below.
        g[K] = std::sin(0.37 * static_cast<double>(i)) + std::cos(0.11 * static_cast<double>(j * j)) +
               0.3 * std::sin(0.7 * static_cast<double>(kz));
        fine_sum += g[K] * cell_volume;
      }
  MPI_Allreduce(MPI_IN_PLACE, &outside, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  CHECK(outside == 0);  // every fine cell's centre lies in the leaf cell it shows

  // The field on the fine cells back to the leaves: sum V f kept (a conservation law).
  std::vector<double> mean;
  view.to_cells(g, 1, mean);
  double cell_sum = 0.0, round_trip = 0.0;
  for (std::size_t c = 0; c < n; ++c) cell_sum += mean[c] * std::pow(leaf[4 * c + 3], dims);
  // A leaf's value to its fine cells and back is itself, to the round-off of
  // summing 4, 16 or 64 equal terms.
  std::vector<double> there, back;
  std::vector<double> level(n);
  for (std::size_t c = 0; c < n; ++c) level[c] = 0.1 * static_cast<double>(c % 7) + 1.0 / 3.0;
  view.to_uniform(level, 1, there);
  view.to_cells(there, 1, back);
  for (std::size_t c = 0; c < n; ++c) round_trip = coflow::test::worst_of(round_trip, std::fabs(back[c] - level[c]));
  double sums[2] = {fine_sum, cell_sum};
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &round_trip, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  INFO(dims << "D: sum V f: fine " << sums[0] << ", leaves " << sums[1] << ", relative difference "
            << std::fabs(sums[1] - sums[0]) / std::fabs(sums[0]) << "; round trip " << round_trip);
  CHECK(std::fabs(sums[1] - sums[0]) <= 2e-14 * std::fabs(sums[0]));  // references.csv: amr_uniform_view_integral
  CHECK(round_trip <= 4e-15);  // references.csv: amr_uniform_view_round_trip
}

}  // namespace

TEST_CASE("amr uniform view: fine cells show their leaf, means keep the integral", "[amr][mpi]") {
  check_view(2);
  check_view(3);
}
