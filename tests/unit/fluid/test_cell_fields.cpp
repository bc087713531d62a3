// fluid/grid cell fields: a checkpoint written from blocks is read back into
// any other blocks (restart on another rank count), and a file of another
// grid or another number of components is refused, naming the file; a value
// that is not finite (a damaged checkpoint), naming the cell.
#include <mpi.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <limits>
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

TEST_CASE("cell fields: a value that is not finite is refused, naming the cell", "[fluid][grid]") {
  const Index3 cells{5, 4, 3};
  const Box whole{{0, 0, 0}, {5, 4, 3}};
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("coflow-cell-fields-nan-" + std::to_string(::getpid()) + ".h5"))
                               .string();
  std::vector<double> populations = block_values(whole, 2), k = block_values(whole, 1);
  populations[2 * ((2 * 4 + 1) * 5 + 3) + 1] =
      std::numeric_limits<double>::quiet_NaN();                       // cell (3, 1, 2), q = 1
  k[(1 * 4 + 3) * 5 + 4] = -std::numeric_limits<double>::infinity();  // cell (4, 3, 1)
  fluid::grid::save_cell_fields(MPI_COMM_SELF, path, 1.5, 7, cells, whole,
                                {{"populations", 2, populations}, {"k", 1, k}});
  CHECK_THROWS_WITH(fluid::grid::load_cell_field(path, "populations", cells, whole, 2),
                    Catch::Contains(path) &&
                        Catch::Contains("'populations' holds a value that is not finite (nan)") &&
                        Catch::Contains("at cell (3, 1, 2), component 1: the checkpoint is damaged"));
  CHECK_THROWS_WITH(fluid::grid::load_cell_field(path, "populations", cells, Box{{2, 1, 1}, {5, 4, 3}}, 2),
                    Catch::Contains("at cell (3, 1, 2), component 1"));
  CHECK_THROWS_WITH(
      fluid::grid::load_cell_field(path, "k", cells, whole, 1),
      Catch::Contains("'k' holds a value that is not finite (-inf) at cell (4, 3, 1): the checkpoint"));
  // A block without the damaged cells reads its own as they are.
  const Box clean{{0, 0, 0}, {3, 4, 3}};
  CHECK(fluid::grid::load_cell_field(path, "populations", cells, clean, 2) == block_values(clean, 2));
  CHECK(fluid::grid::load_cell_field(path, "k", cells, clean, 1) == block_values(clean, 1));
  std::filesystem::remove(path);
}

TEST_CASE("cell fields: a number beside them comes back to the bit; absent, the default; damaged, refused",
          "[fluid][grid]") {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("coflow-number-" + std::to_string(::getpid()) + ".txt"))
          .string();
  std::filesystem::remove(path);
  CHECK(fluid::grid::load_number(path, 0.0) == 0.0);  // a checkpoint from before the number
  const double u2 = 0.1 / 3.0 * 1.0e-3;               // no short decimal
  fluid::grid::save_number(MPI_COMM_SELF, path, u2);
  CHECK(fluid::grid::load_number(path, 0.0) == u2);
  for (const char* bad : {"", "x", "0x1p-3junk", "0x1p-3 junk", "nan", "inf", "-0x1p-3"}) {
    {
      std::ofstream out(path);
      out << bad << "\n";
    }
    CHECK_THROWS_WITH(fluid::grid::load_number(path, 0.0),
                      Catch::Contains(path) && Catch::Contains("damaged checkpoint"));
  }
  std::filesystem::remove(path);
}
