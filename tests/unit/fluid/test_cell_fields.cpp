// fluid/grid cell fields: a checkpoint written from blocks is read back into
// any other blocks (restart on another rank count), and a file of another
// grid or another number of components is refused, naming the file.
#include <mpi.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "fluid/grid/cell_fields.hpp"

using namespace coflow;
using coupler::Box;
using coupler::Index3;

namespace {

double value(long i, long j, long k, int q) { return 1000.0 * k + 100.0 * j + 10.0 * i + q + 0.25; }

std::vector<double> block_values(const Box& b, int C) {
  std::vector<double> v;
  for (long k = b.lo[2]; k < b.hi[2]; ++k)
    for (long j = b.lo[1]; j < b.hi[1]; ++j)
      for (long i = b.lo[0]; i < b.hi[0]; ++i)
        for (int q = 0; q < C; ++q) v.push_back(value(i, j, k, q));
  return v;
}

}  // namespace

TEST_CASE("cell fields: saved whole, loaded by any block; another grid is refused", "[fluid][grid]") {
  const Index3 cells{5, 4, 3};
  const Box whole{{0, 0, 0}, {5, 4, 3}};
  const std::string path =
      (std::filesystem::temp_directory_path() / ("coflow-cell-fields-" + std::to_string(::getpid()) + ".h5")).string();
  const std::vector<double> all = block_values(whole, 2);
  const std::vector<double> pressure = block_values(whole, 1);
  fluid::grid::save_cell_fields(MPI_COMM_SELF, path, 1.5, 7, cells, whole,
                                {{"populations", 2, all}, {"pressure", 1, pressure}});
  // Blocks of another decomposition read exactly their own cells.
  for (const Box& b : {Box{{0, 0, 0}, {2, 4, 3}}, Box{{2, 1, 1}, {5, 4, 3}}, whole}) {
    CHECK(fluid::grid::load_cell_field(path, "populations", cells, b, 2) == block_values(b, 2));
    CHECK(fluid::grid::load_cell_field(path, "pressure", cells, b, 1) == block_values(b, 1));
  }
  CHECK_THROWS_WITH(fluid::grid::load_cell_field(path, "populations", {5, 4, 4}, whole, 2),
                    Catch::Contains(path) && Catch::Contains("another grid"));
  CHECK_THROWS_WITH(fluid::grid::load_cell_field(path, "populations", cells, whole, 19),
                    Catch::Contains("19 per cell"));
  std::filesystem::remove(path);
}
