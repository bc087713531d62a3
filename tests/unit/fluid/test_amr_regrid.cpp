// fv's adaptive grid regridding (fluid/fv/amr): a bump that moves is
// followed by refinement where the field varies and coarsening where it is
// flat; the field's integral is kept to round-off through every regrid
// (conservative transfer), the leaves stay balanced over the ranks, the
// ghost leaves carry their owners' values, 1 rank equals N ranks bit for
// bit, and a saved forest whose values are damaged is refused on loading.
// `unit.mpi` runs these on 2 ranks, `unit.mpi_4_ranks` the one comparing 1
// rank with N on 4.
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "amr_testing.hpp"
#include "fluid/fv/amr/composite_grid.hpp"
#include "fluid/fv/amr/forest.hpp"
#include "fluid/fv/amr/refinement_criteria.hpp"

using namespace coflow::fluid::fv::amr;

namespace {

constexpr double kTree = 0.25;  // 4 x 4 (x 4) trees on the unit square (cube)

ForestSpec moving_bump_spec(int dims) {
  ForestSpec s;
  s.dims = dims;
  s.trees = {4, 4, dims == 3 ? 4 : 1};
  s.max_level = 2;
  s.patch = 4;
  s.components = 2;  // the bump and a second, constant component
  return s;
}

std::array<double, 3> centre(const ForestSpec& s, const Leaf& leaf, long cell) {
  const long n = s.patch;
  const double h = kTree / static_cast<double>(n << leaf.level);
  const std::array<long, 3> in{cell % n, (cell / n) % n, cell / (n * n)};
  std::array<double, 3> x{0.0, 0.0, 0.0};
  for (int d = 0; d < s.dims; ++d) x[d] = (static_cast<double>(leaf.patch[d] * n + in[d]) + 0.5) * h;
  return x;
}

// A Gaussian bump of width 0.08 at `c`.
double bump(const std::array<double, 3>& x, const std::array<double, 3>& c, int dims) {
  double r2 = 0.0;
  for (int d = 0; d < dims; ++d) r2 += (x[d] - c[d]) * (x[d] - c[d]);
  return std::exp(-r2 / (0.08 * 0.08));
}

void fill(Forest& f, const std::array<double, 3>& c) {
  const auto& s = f.spec();
  const long cells = s.values_per_leaf() / s.components;
  for (std::size_t l = 0; l < f.leaves().size(); ++l)
    for (long cell = 0; cell < cells; ++cell) {
      f.data(l)[static_cast<std::size_t>(2 * cell)] = bump(centre(s, f.leaves()[l], cell), c, s.dims);
      f.data(l)[static_cast<std::size_t>(2 * cell + 1)] = 1.0 + f.leaves()[l].level;
    }
}

// The integral of component q over the domain, and its magnitude.
double integral(const Forest& f, int q) {
  const auto& s = f.spec();
  double sum = 0.0;
  for (std::size_t l = 0; l < f.leaves().size(); ++l) {
    const double volume = std::pow(kTree / (s.patch << f.leaves()[l].level), s.dims);
    const auto v = f.data(l);
    for (std::size_t c = static_cast<std::size_t>(q); c < v.size(); c += 2) sum += volume * v[c];
  }
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, f.comm());
  return sum;
}

struct Outcome {
  double worst_drift = 0.0;  // |integral after - before| / integral, worst regrid
  long leaves_spread = 0;    // most minus fewest leaves per rank, worst regrid
  std::vector<long> global_leaves;
  std::map<std::array<long, 5>, double> values;  // (level, patch, cell) -> bump value
};

// Four regrids following the bump along a diagonal: each fills the field at
// the bump's new place, marks by variation and adapts twice (refinement
// spreads one level per regrid).
Outcome follow_bump(MPI_Comm comm, int dims) {
  Forest forest(comm, moving_bump_spec(dims));
  Outcome out;
  for (int step = 0; step < 4; ++step) {
    const double t = 0.3 + 0.12 * step;
    fill(forest, {t, t, dims == 3 ? t : 0.0});
    for (int pass = 0; pass < 2; ++pass) {
      const double before0 = integral(forest, 0), before1 = integral(forest, 1);
      forest.adapt(mark_by_variation(forest, 0, 0.05, 0.01));
      for (const double drift : {std::fabs(integral(forest, 0) - before0) / before0,
                                 std::fabs(integral(forest, 1) - before1) / before1})
        out.worst_drift = coflow::test::worst_of(out.worst_drift, drift);
      long n = static_cast<long>(forest.leaves().size()), most = n, fewest = n;
      MPI_Allreduce(MPI_IN_PLACE, &most, 1, MPI_LONG, MPI_MAX, comm);
      MPI_Allreduce(MPI_IN_PLACE, &fewest, 1, MPI_LONG, MPI_MIN, comm);
      out.leaves_spread = std::max(out.leaves_spread, most - fewest);
      out.global_leaves.push_back(forest.global_leaves());
    }
  }
  for (std::size_t l = 0; l < forest.leaves().size(); ++l) {
    const auto& leaf = forest.leaves()[l];
    for (std::size_t c = 0; 2 * c < forest.data(l).size(); ++c)
      out.values[{leaf.level, leaf.patch[0], leaf.patch[1], leaf.patch[2], static_cast<long>(c)}] =
          forest.data(l)[2 * c];
  }
  return out;
}

}  // namespace

TEST_CASE("amr regrid: conservative transfer and balanced ranks", "[amr][mpi]") {
  for (int dims : {2, 3}) {
    const auto o = follow_bump(MPI_COMM_WORLD, dims);
    INFO(dims << "D: worst relative drift of the integrals " << o.worst_drift << ", leaves spread "
              << o.leaves_spread);
    CHECK(o.worst_drift <= 2e-13);  // references.csv: amr_regrid_conservation
    // p4est keeps families on one rank: each partition boundary moves by
    // less than a family, so two ranks differ by at most 2 (2^d - 1) leaves.
    CHECK(o.leaves_spread <= 2 * ((1 << dims) - 1));
    // It refined and coarsened: the leaf count went up and came down.
    const auto [lo, hi] = std::minmax_element(o.global_leaves.begin(), o.global_leaves.end());
    CHECK(*hi > *lo);
    CHECK(std::adjacent_find(o.global_leaves.begin(), o.global_leaves.end(), std::greater<>()) !=
          o.global_leaves.end());
  }
}

TEST_CASE("amr regrid: 1 rank equals N ranks bit for bit", "[amr][mpi]") {
  for (int dims : {2, 3}) {
    const auto alone = follow_bump(MPI_COMM_SELF, dims);
    const auto shared = follow_bump(MPI_COMM_WORLD, dims);
    CHECK(alone.global_leaves == shared.global_leaves);
    long missing = 0;
    const double worst = coflow::test::largest_difference(shared.values, alone.values, &missing);
    INFO(dims << "D: largest difference " << worst << ", cells missing " << missing);
    CHECK(missing == 0);
    CHECK(worst <= 0.0);  // references.csv: amr_regrid_ranks_1_vs_4
  }
}

TEST_CASE("amr regrid: ghost leaves carry their owners' values", "[amr][mpi]") {
  for (int dims : {2, 3}) {
    Forest forest(MPI_COMM_WORLD, moving_bump_spec(dims));
    fill(forest, {0.4, 0.45, 0.5});
    forest.adapt(mark_by_variation(forest, 0, 0.05, 0.01));
    fill(forest, {0.4, 0.45, 0.5});
    forest.exchange_ghosts();
    const auto& s = forest.spec();
    long wrong = 0;
    for (std::size_t g = 0; g < forest.ghosts().size(); ++g)
      for (long cell = 0; cell < s.values_per_leaf() / 2; ++cell) {
        const auto& leaf = forest.ghosts()[g];
        wrong += forest.ghost_data(g)[static_cast<std::size_t>(2 * cell)] !=
                 bump(centre(s, leaf, cell), {0.4, 0.45, 0.5}, dims);
        wrong += forest.ghost_data(g)[static_cast<std::size_t>(2 * cell + 1)] != 1.0 + leaf.level;
      }
    CHECK(wrong == 0);
    int size = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    long ghosts = static_cast<long>(forest.ghosts().size());
    MPI_Allreduce(MPI_IN_PLACE, &ghosts, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    if (size > 1) CHECK(ghosts > 0);  // on one rank there are none to check
  }
}

TEST_CASE("amr regrid: geometric criteria (box, walls, points) refine where they say", "[amr][mpi]") {
  // Unit square, 4 x 4 trees of 0.25, 4^2-cell patches; walls along x, periodic along y.
  Forest forest(MPI_COMM_WORLD, coflow::test::forest_2d({4, 4, 1}, {false, true, false}, 1, 4, 0));
  const CompositeGrid g(forest, {{0.0, 0.0, 0.0}, 0.25});
  const auto count = [&](const std::vector<int>& m) {
    long n = std::count(m.begin(), m.end(), 1);
    MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    return n;
  };
  // [0.3, 0.6] x [0.1, 0.2] overlaps trees x 1..2, y 0: 2 leaves.
  CHECK(count(mark_in_box(g, {0.3, 0.1, 0.0}, {0.6, 0.2, 0.0})) == 2);
  // Within 0.1 of x = 0 or x = 1 (y periodic: no walls): the first and last columns, 8 leaves.
  CHECK(count(mark_near_walls(g, 0.1)) == 8);
  // Two points in one leaf, one in another: 2 leaves (each rank marks its own).
  CHECK(count(mark_at_points(g, {{0.1, 0.1, 0.0}, {0.2, 0.2, 0.0}, {0.9, 0.6, 0.0}})) == 2);
  // After refining the box's leaves, the box marks the children that overlap it.
  forest.adapt(mark_in_box(g, {0.3, 0.1, 0.0}, {0.6, 0.2, 0.0}));
  const CompositeGrid refined(forest, {{0.0, 0.0, 0.0}, 0.25});
  const auto marks = mark_in_box(refined, {0.3, 0.1, 0.0}, {0.6, 0.2, 0.0});
  long fine = 0;
  for (std::size_t l = 0; l < marks.size(); ++l) fine += marks[l] == 1 && forest.leaves()[l].level == 1;
  MPI_Allreduce(MPI_IN_PLACE, &fine, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  // x in [0.25, 0.375), [0.375, 0.5), [0.5, 0.625) (not [0.625, 0.75)); y in [0, 0.125), [0.125, 0.25).
  CHECK(fine == 6);
}

// A saved forest loads with its values; one whose values hold a NaN (a
// damaged checkpoint) is refused on every rank, naming the file.
TEST_CASE("amr regrid: a loaded forest with a value that is not finite is refused", "[amr][mpi]") {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  long id = rank == 0 ? static_cast<long>(::getpid()) : 0;
  MPI_Bcast(&id, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  for (int dims : {2, 3}) {
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("coflow-forest-" + std::to_string(id) + "-" + std::to_string(dims) + ".p4est"))
                                 .string();
    Forest forest(MPI_COMM_WORLD, moving_bump_spec(dims));
    fill(forest, {0.4, 0.45, 0.5});
    forest.save(path);
    CHECK_NOTHROW(Forest(MPI_COMM_WORLD, moving_bump_spec(dims), path));
    if (rank == 0 && !forest.leaves().empty()) forest.data(0)[3] = std::numeric_limits<double>::quiet_NaN();
    forest.save(path);
    CHECK_THROWS_WITH(Forest(MPI_COMM_WORLD, moving_bump_spec(dims), path),
                      Catch::Contains(path) && Catch::Contains("holds a cell value that is not finite") &&
                          Catch::Contains("the checkpoint is damaged"));
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) std::filesystem::remove(path);
  }
}
