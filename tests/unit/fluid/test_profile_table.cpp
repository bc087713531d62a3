// A velocity face's tabulated profile (fluid/params.hpp, profile: table):
// linear between rows, the end rows' factor beyond them, comments and a
// header skipped, and a bad file refused with the line at fault; and the
// profiles on the ghost lines beyond the box.
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <string>

#include "fluid/params.hpp"

using coflow::fluid::read_profile_table;

namespace {
std::string write(const std::string& name, const std::string& text) {
  const std::string path = std::string(P_tmpdir) + "/coflow_" + name;
  std::ofstream(path) << text;
  return path;
}
}  // namespace

TEST_CASE("profile table: linear between rows, clamped beyond them", "[fluid]") {
  const auto path = write("profile_ok.csv",
                          "# u / U across a duct\ny, factor\n0.0, 0.0\n0.5 1.0  # blanks too\n\n2.0, 0.25\n");
  const auto t = read_profile_table(path, 1);
  CHECK(t.axis == 1);
  REQUIRE(t.at.size() == 3);
  CHECK(t(0.25) == 0.5);    // halfway between the first two rows
  CHECK(t(1.25) == 0.625);  // halfway between the last two
  CHECK(t(0.5) == 1.0);     // on a row
  CHECK(t(-1.0) == 0.0);    // before the first row: its factor
  CHECK(t(3.0) == 0.25);    // after the last
  std::remove(path.c_str());
}

TEST_CASE("profile table: a bad file names the line at fault", "[fluid]") {
  const auto one = write("profile_one.csv", "0.0, 1.0\n");
  CHECK_THROWS_WITH(read_profile_table(one, 1), Catch::Contains("two rows at least"));
  const auto back = write("profile_back.csv", "0.0, 1.0\n1.0, 1.0\n0.5, 1.0\n");
  CHECK_THROWS_WITH(read_profile_table(back, 1), Catch::Contains("must increase row to row (line 3 of"));
  const auto three = write("profile_three.csv", "y, f\n0.0, 1.0, 2.0\n");
  CHECK_THROWS_WITH(read_profile_table(three, 1),
                    Catch::Contains("two numbers, coordinate and factor (line 2 of"));
  CHECK_THROWS_WITH(read_profile_table("/nonexistent/profile.csv", 1),
                    Catch::Contains("/nonexistent/profile.csv: no such file"));
  for (const auto& p : {one, back, three}) std::remove(p.c_str());
}

TEST_CASE("profile columns: k and epsilon across an inlet, one table each", "[fluid]") {
  const auto path = write("profile_ke.csv",
                          "y, k, epsilon\n0.0, 1.0e-6, 5.0e-8\n0.5, 3.0e-6, 1.5e-7\n1.0, 2.0e-6, 1.0e-7\n");
  const auto t = coflow::fluid::read_profile_columns(path, 1, {"k", "epsilon"});
  REQUIRE(t.size() == 2);
  CHECK(t[0].axis == 1);
  CHECK(t[0](0.25) == Approx(2.0e-6).epsilon(1e-15));
  CHECK(t[1](0.75) == Approx(1.25e-7).epsilon(1e-15));
  CHECK(t[1](2.0) == 1.0e-7);
  const auto two = write("profile_ke_two.csv", "0.0, 1.0e-6\n1.0, 2.0e-6\n");
  CHECK_THROWS_WITH(
      coflow::fluid::read_profile_columns(two, 1, {"k", "epsilon"}),
      Catch::Contains("three numbers, coordinate, k and epsilon (line 2 of"));  // line 1: a header
  for (const auto& p : {path, two}) std::remove(p.c_str());
}

// The ghost lines beyond a face's neighbouring faces ask for the profile
// outside the box: the parabola and the table take their value on the box's
// edge there (the parabola went negative, 4 s (1 - s) < 0, before
// 2026-12-05, and fed k-epsilon's strain in the corner cells a wrong ghost).
TEST_CASE("velocity face profiles: ghost lines beyond the box take the edge's value", "[fluid]") {
  coflow::config::Config cfg;
  cfg.domain.lower = {0.0, 0.0, 0.0};
  cfg.domain.upper = {1.0, 1.0, 0.1};
  cfg.domain.cells = {16, 16, 1};
  cfg.domain.periodic = {false, false, true};
  coflow::fluid::BoundaryParams b;
  b.type = "velocity";
  b.profile = "parabolic";
  const double inside[3] = {0.0, 0.5, 0.5}, beyond[3] = {0.0, -0.5 / 16, 0.5},
               past[3] = {0.0, 1.0 + 1.5 / 16, 0.5};
  CHECK(b.profile_factor(0, inside, cfg) == 1.0);  // x-: the parabola across y
  CHECK(b.profile_factor(0, beyond, cfg) == 0.0);
  CHECK(b.profile_factor(0, past, cfg) == 0.0);
}
