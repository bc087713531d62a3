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

// sum(comm, terms) on the terms of all_terms(10001): all of them on this rank
// alone in order, then dealt out to the world's ranks and shuffled, twice.
struct Layouts {
  std::vector<double> terms, one, split, again;
};
template <class Sum>
Layouts three_layouts(Sum sum) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  Layouts l;
  l.terms = all_terms(10001);
  l.one = sum(MPI_COMM_SELF, l.terms);
  l.split = sum(MPI_COMM_WORLD, my_share(l.terms, rank, size, 7));
  l.again = sum(MPI_COMM_WORLD, my_share(l.terms, size - 1 - rank, size, 99));
  return l;
}

}  // namespace

TEST_CASE("reproducible sums: the same bits on 1 rank and on N, in any order", "[coupler][mpi]") {
  const Layouts l =
      three_layouts([](MPI_Comm c, const std::vector<double>& t) { return reproducible_sums(c, t, 3); });
  const auto &t = l.terms, &one = l.one, &split = l.split, &again = l.again;
  const std::size_t n = t.size() / 3;
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

namespace {

// The terms of my_share added one at a time to exact sums of 3 values.
std::vector<double> exact_sums(MPI_Comm comm, const std::vector<double>& terms) {
  coflow::coupler::ExactSums sums(3);
  for (std::size_t k = 0; k < terms.size(); ++k) sums.add(k % 3, terms[k]);
  return sums.reduce(comm);
}

}  // namespace

TEST_CASE("exact sums: the same bits on 1 rank and on N, exact where the sum is a double", "[coupler][mpi]") {
  const Layouts l = three_layouts(exact_sums);
  const auto &t = l.terms, &one = l.one, &split = l.split, &again = l.again;
  const std::size_t n = t.size() / 3;
  std::int64_t exact = 0;
  for (std::size_t r = 0; r < n; ++r) exact += static_cast<std::int64_t>(t[3 * r + 1]);
  const auto reproducible = reproducible_sums(MPI_COMM_SELF, t, 3);
  for (std::size_t c = 0; c < 3; ++c) {
    INFO("column " << c << ": " << one[c] << " " << split[c] << " " << again[c]);
    CHECK(std::fabs(split[c] - one[c]) <= 0);
    CHECK(std::fabs(again[c] - one[c]) <= 0);
  }
  CHECK(one[1] == static_cast<double>(exact));
  CHECK(one[2] == 0.5 * static_cast<double>(n - 2));
  // Column 0 against the pre-rounded sums (error about 1e-23 of the largest
  // term): both within a few units in the last place of the exact sum.
  CHECK(std::fabs(one[0] - reproducible[0]) <= 4 * std::ldexp(std::fabs(one[0]), -52));
}

TEST_CASE("exact sums: the whole range of doubles, signs, NaN and infinity", "[coupler][mpi]") {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const double tiny = std::numeric_limits<double>::denorm_min();  // 2^-1074
  const double inf = std::numeric_limits<double>::infinity();
  coflow::coupler::ExactSums s(6);
  if (rank == 0) {
    for (double x : {1e308, 1e308, -1e308}) s.add(0, x);  // left to right: infinity
    for (double x : {tiny, tiny, -tiny, -tiny, -tiny}) s.add(1, x);
    for (double x : {1e300, 1e-300, -1e300}) s.add(2, x);
    for (double x : {-0.75, -0.5, 0.25}) s.add(3, x);
    s.add(4, inf);
    s.add(5, inf);
    s.add(5, -inf);
  }
  const auto sum = s.reduce(MPI_COMM_WORLD);
  CHECK(sum[0] == 1e308);
  CHECK(sum[1] == -tiny);
  CHECK(sum[2] == 1e-300);
  CHECK(sum[3] == -1.0);
  CHECK(sum[4] == inf);
  CHECK(std::isnan(sum[5]));
  const auto zero = s.reduce(MPI_COMM_WORLD);  // reduce zeroed the sums
  CHECK(zero == std::vector<double>(6, 0.0));
}

TEST_CASE("exact sums: merged, gathered on rank 0 and written out, the same sums as added at once",
          "[coupler][mpi]") {
  // Terms spread over 2^-1074 .. 1e300 with both signs, a subnormal among them.
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const std::vector<double> terms{1e300, -3.5e-310, 0.1,      -1e-300, 7.25,
                                  1e300, -1e300,    4.9e-324, -0.3,    2.0 / 3.0};
  coflow::coupler::ExactSums once(2), merged(2), part(2);
  for (std::size_t k = 0; k < terms.size(); ++k) {
    once.add(k % 2, std::ldexp(terms[k], rank));  // times 2^rank: exact
    part.add(k % 2, std::ldexp(terms[k], rank));
    if (k % 3 == 2) {  // merged in pieces, as windows are
      merged.merge(part);
      part = coflow::coupler::ExactSums(2);
    }
  }
  merged.merge(part);
  coflow::coupler::ExactSums gathered = merged;
  gathered.to_root(MPI_COMM_WORLD);
  // Written out and read back (a checkpoint), on rank 0 only, as ImpulseSeries does.
  coflow::coupler::ExactSums restored(2);
  if (rank == 0)
    for (std::size_t i = 0; i < 2; ++i) restored.set(i, gathered.canonical(i), gathered.special(i));
  const auto a = once.reduce(MPI_COMM_WORLD), b = merged.reduce(MPI_COMM_WORLD),
             c = gathered.reduce(MPI_COMM_WORLD), d = restored.reduce(MPI_COMM_WORLD);
  for (std::size_t i = 0; i < 2; ++i) {
    INFO("value " << i << ": " << a[i] << " " << b[i] << " " << c[i] << " " << d[i]);
    CHECK(std::fabs(b[i] - a[i]) <= 0);
    CHECK(std::fabs(c[i] - a[i]) <= 0);
    CHECK(std::fabs(d[i] - a[i]) <= 0);
  }
  // Column 0 holds (1e300 + 0.1 + 7.25 - 1e300 - 0.3) (2^size - 1) (up to 6
  // ranks; the tests run on 1, 2 and 4): the exact
  // sum of 0.1, 7.25 and -0.3 (58 bits, exact in x86's 64-bit long double, as
  // is its product by 2^size - 1), rounded once.
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const long double exact = (static_cast<long double>(0.1) + 7.25L - static_cast<long double>(0.3)) *
                            static_cast<long double>((1 << size) - 1);
  CHECK(a[0] == static_cast<double>(exact));
  CHECK_THROWS_AS(merged.merge(coflow::coupler::ExactSums(3)), std::logic_error);
}
