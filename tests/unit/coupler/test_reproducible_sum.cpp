// coupler::reproducible_sums: the same bits whatever the order of the terms
// and however they are split among the ranks (Demmel & Nguyen 2015), and
// sums that are exact where the exact sum is a double. Runs on any rank
// count (`unit` 1 rank, `unit.mpi` 2, `unit.mpi_4_ranks` 4).
#include <mpi.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "coflow/reproducible_sum.hpp"

using coflow::coupler::reproducible_sums;

namespace {

// n rows of 3 terms, the same on every rank: column 0 of magnitudes spread
// over 30 binades and both signs, column 1 integers below 2^40 (their exact
// sum an int64), column 2 a large pair that cancels with small terms between.
std::vector<double> all_terms(std::size_t n) {
  std::mt19937_64 gen(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0), p(-15.0, 15.0);
  std::uniform_int_distribution<std::int64_t> i(-(std::int64_t{1} << 40), std::int64_t{1} << 40);
  std::vector<double> t(3 * n);
  for (std::size_t r = 0; r < n; ++r) {
    t[3 * r] = u(gen) * std::exp2(p(gen));
    t[3 * r + 1] = static_cast<double>(i(gen));
    t[3 * r + 2] = r == 0 ? 1e16 : r == n - 1 ? -1e16 : 0.5;
  }
  return t;
}

// This rank's share of the rows: every size-th row from a rank-dependent
// start, in a shuffled order.
std::vector<double> my_share(const std::vector<double>& t, int rank, int size, unsigned seed) {
  std::vector<std::size_t> rows;
  for (std::size_t r = static_cast<std::size_t>(rank); r < t.size() / 3; r += static_cast<std::size_t>(size))
    rows.push_back(r);
  std::shuffle(rows.begin(), rows.end(), std::mt19937(seed));
  std::vector<double> mine;
  for (std::size_t r : rows) mine.insert(mine.end(), {t[3 * r], t[3 * r + 1], t[3 * r + 2]});
  return mine;
}

}  // namespace

TEST_CASE("reproducible sums: the same bits on 1 rank and on N, in any order", "[coupler][mpi]") {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const std::size_t n = 10001;
  const std::vector<double> t = all_terms(n);
  const auto one = reproducible_sums(MPI_COMM_SELF, t, 3);  // every term on this rank alone, in order
  const auto split = reproducible_sums(MPI_COMM_WORLD, my_share(t, rank, size, 7), 3);
  const auto again = reproducible_sums(MPI_COMM_WORLD, my_share(t, size - 1 - rank, size, 99), 3);
  std::int64_t exact = 0;  // column 1's exact sum
  for (std::size_t r = 0; r < n; ++r) exact += static_cast<std::int64_t>(t[3 * r + 1]);
  double plain[3] = {0, 0, 0};  // left to right: round-off in column 0, the 0.5s lost in column 2
  for (std::size_t r = 0; r < n; ++r)
    for (int c = 0; c < 3; ++c) plain[c] += t[3 * r + static_cast<std::size_t>(c)];
  for (int c = 0; c < 3; ++c) {
    const auto C = static_cast<std::size_t>(c);
    INFO("column " << c << ": " << one[C] << " " << split[C] << " " << again[C] << " plain " << plain[c]
                   << ", plain - reproducible " << plain[c] - one[C]);
    CHECK(std::fabs(split[C] - one[C]) <= 0);
    CHECK(std::fabs(again[C] - one[C]) <= 0);
  }
  CHECK(one[1] == static_cast<double>(exact));
  CHECK(one[2] == 0.5 * static_cast<double>(n - 2));  // 4999.5: exact
  CHECK(plain[2] != one[2]);                          // the plain sum loses the halves beside 1e16
  // The plain left-to-right sum's round-off: 1.96e-10 measured (sum -12757.8).
  CHECK(std::fabs(one[0] - plain[0]) <= 2e-9);
}

TEST_CASE("reproducible sums: zeros, no terms, and a NaN", "[coupler][mpi]") {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  std::vector<double> t = {0.0, 1.0, 2.0, 0.0, -1.0, 3.0};
  if (rank == 0) t[2] = std::numeric_limits<double>::quiet_NaN();
  const auto s = reproducible_sums(MPI_COMM_WORLD, t, 3);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  CHECK(s[0] == 0.0);
  CHECK(s[1] == 0.0);
  CHECK(std::isnan(s[2]));
  const auto none = reproducible_sums(MPI_COMM_WORLD, std::vector<double>{}, 2);
  CHECK(none == std::vector<double>{0.0, 0.0});
  CHECK_THROWS_AS(reproducible_sums(MPI_COMM_SELF, t, 4), std::logic_error);
}
