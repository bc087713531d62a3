// fv's adaptive grid written for ParaView (fluid/fv/amr/composite_output):
// on a 2-level 2D and a 3-level 3D forest, the file holds every level's
// cells once (counts, volumes summing to the domain's) with their values,
// read back from the HDF5 file. The ctest output.paraview_reads_amr then
// opens the XDMF files with ParaView (tests/output/check_amr_xdmf.py): the
// files stay in $COFLOW_AMR_OUT (default: amr-output-<ranks> in the working
// folder).
#include <fmt/format.h>
#include <mpi.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "amr_testing.hpp"
#include "coflow/output.hpp"
#include "fluid/fv/amr/composite_output.hpp"

using namespace coflow::fluid::fv::amr;

namespace {

double field(const std::array<double, 3>& x) {
  return 1.0 + x[0] + 10.0 * x[1] + 100.0 * x[2];
}

void write_and_read(int dims, int levels) {
  ForestSpec s;
  s.dims = dims;
  s.trees = {2, 2, dims == 3 ? 2 : 1};
  s.max_level = levels - 1;
  s.patch = 4;
  s.components = 2;
  s.refine = [](int level, const Index3& p) { return p[0] == 0 && p[1] < (1 << level); };
  Forest forest(MPI_COMM_WORLD, s);
  // A 2D grid sits at its domain's z (here 0.3), as the uniform snapshots do.
  const CompositeGrid g(forest, {{0.0, 0.0, dims == 2 ? 0.3 : 0.0}, 0.5});
  for (long c = 0; c < g.local_cells(); ++c) {
    auto v = forest.data(static_cast<std::size_t>(c / g.cells_per_patch()));
    v[static_cast<std::size_t>(c % g.cells_per_patch()) * 2 + 1] = field(g.centre(g.local_cell(c)));
  }
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  // unit and unit.mpi may run at once: a folder per rank count.
  const char* env = std::getenv("COFLOW_AMR_OUT");
  const std::string dir = env ? env : fmt::format("amr-output-{}", size);
  if (rank == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  const std::string stem = fmt::format("composite_{}d", dims);
  write_composite(g, dir, stem, 1.5, 7, {{"value", 1, 1}});
  if (rank != 0) return;
  const int corners = dims == 3 ? 8 : 4;
  double volume = 0.0, worst = 0.0;
  std::size_t cells = 0;
  for (int l = 0; l < levels; ++l) {
    std::vector<std::size_t> shape;
    const auto nodes =
        coflow::output::read_dataset(dir + "/" + stem + ".h5", fmt::format("level{}_nodes", l), &shape);
    const auto values =
        coflow::output::read_dataset(dir + "/" + stem + ".h5", fmt::format("level{}_value", l));
    const std::size_t n = values.size();
    REQUIRE(nodes.size() == n * corners * 3);
    for (std::size_t c = 0; c < n; ++c) {
      std::array<double, 3> centre{0.0, 0.0, 0.0}, lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
      for (int k = 0; k < corners; ++k)
        for (std::size_t d = 0; d < 3; ++d) {
          const double x = nodes[(c * corners + k) * 3 + d];
          centre[d] += x / corners;
          lo[d] = std::min(lo[d], x);
          hi[d] = std::max(hi[d], x);
        }
      double v = 1.0;
      for (int d = 0; d < dims; ++d) v *= hi[d] - lo[d];
      volume += v;
      worst = coflow::test::worst_of(worst, std::fabs(values[c] - field(centre)));
    }
    cells += n;
  }
  INFO(dims << "D, " << levels << " levels: cells " << cells << " of " << g.global_cells() << ", volume "
            << volume << ", largest value error " << worst);
  CHECK(cells == static_cast<std::size_t>(g.global_cells()));
  CHECK(std::fabs(volume - 1.0) <= 1e-12);
  CHECK(worst <= 1e-12);  // references.csv: amr_output_readback
}

}  // namespace

TEST_CASE("amr output: every level's cells once, with their values", "[amr][mpi][amr_output]") {
  write_and_read(2, 2);
  write_and_read(3, 3);
}

TEST_CASE("amr grid: a point that is not finite, or far out, lies in no cell", "[amr][mpi][amr_output]") {
  ForestSpec s;
  s.dims = 2;
  s.trees = {2, 2, 1};
  s.max_level = 0;
  s.patch = 4;
  s.components = 1;
  Forest forest(MPI_COMM_WORLD, s);
  const CompositeGrid g(forest, {{0.0, 0.0, 0.0}, 0.5});
  long c = -1;
  CHECK_FALSE(g.locate({std::nan(""), 0.5, 0.0}, &c));
  CHECK_FALSE(g.locate({0.25, HUGE_VAL, 0.0}, &c));
  CHECK_FALSE(g.locate({1e300, 0.5, 0.0}, &c));  // finite, but its index would not fit a long
  CHECK(c == -1);
}
