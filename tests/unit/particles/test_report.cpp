// The particles' part of the pre-run report: an initial file whose radii
// are smaller than the species' diameter is a warning that counts them; a
// file with larger grains, other species, none at all, or in the run's own
// folders is bad input.
#include <mpi.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "coflow/catalog.hpp"
#include "coflow/output.hpp"
#include "coflow/report.hpp"
#include "coflow/run_config.hpp"
#include "particles/particles_interface.hpp"

using namespace coflow;

namespace {

config::Report report_for(const std::string& file, double diameter) {
  const std::string text = "run: {name: r, end_time: 0.1}\n"
                           "domain: {lower: [0, 0, 0], upper: [0.1, 0.1, 0.1], cells: [10, 10, 10]}\n"
                           "particles:\n  solver: dem\n  species: {grain: {density: 2500.0, diameter: " +
                           std::to_string(diameter) + "}}\n  initial: [{file: {path: " + file + "}}]\n";
  const auto cfg = config::parse_config_node(YAML::Load(text), "report.yaml", catalog());
  return config::pre_run_report(cfg, catalog());
}

}  // namespace

TEST_CASE("pre-run report: initial file radii against the species diameter", "[report]") {
  const std::string file =
      (std::filesystem::temp_directory_path() / ("coflow-report-" + std::to_string(::getpid()) + ".h5")).string();
  // Three grains of species 0: two of diameter 0.01 m, one of 0.012 m.
  const std::vector<std::int64_t> id{0, 1, 2};
  const std::vector<std::int32_t> species{0, 0, 0};
  const std::vector<double> x{0.02, 0.02, 0.02, 0.05, 0.05, 0.05, 0.08, 0.08, 0.08}, zero(9, 0.0);
  const std::vector<double> radius{0.005, 0.005, 0.006};
  output::write_points(MPI_COMM_SELF, file, 0.0, 0, 3, id, species,
                       {{"position", 3, x}, {"velocity", 3, zero}, {"angular_velocity", 3, zero}, {"radius", 1, radius}});
  const config::Report r = report_for(file, 0.012);
  REQUIRE(r.warnings.size() == 1);  // smaller grains than the species: the file's radii are used
  CHECK_THAT(r.warnings[0], Catch::Contains("2 of the 3 particles") && Catch::Contains("diameter 0.01 m") &&
                                Catch::Contains("species 'grain' says 0.012 m"));
  // A grain larger than its species allows is bad input (the ghost layers are
  // as wide as the species' largest diameter; before 2026-12-05 a warning,
  // and the particles stopped at the start).
  CHECK_THROWS_WITH(report_for(file, 0.01),
                    Catch::Contains("particles.initial[0].file.path: particle 2 of " + file +
                                    " has a diameter of 0.012 m, but species 'grain' is at most 0.01 m"));
  std::filesystem::remove(file);
}

TEST_CASE("an initial file with another run's species, unreadable, or in the run's own folders is bad input",
          "[report]") {
  const auto tmp = std::filesystem::temp_directory_path();
  const std::string file = (tmp / ("coflow-species-" + std::to_string(::getpid()) + ".h5")).string();
  const std::vector<std::int64_t> id{0, 1};
  const std::vector<std::int32_t> species{0, 1};  // written by a run with two species
  const std::vector<double> x{0.02, 0.02, 0.02, 0.05, 0.05, 0.05}, zero(6, 0.0), radius{0.005, 0.005};
  output::write_points(
      MPI_COMM_SELF, file, 0.0, 0, 2, id, species,
      {{"position", 3, x}, {"velocity", 3, zero}, {"angular_velocity", 3, zero}, {"radius", 1, radius}});
  CHECK_THROWS_WITH(report_for(file, 0.01), Catch::Contains("initial[0].file.path: particle 1 of " + file +
                                                            " has species 1, but this run defines 1"));
  std::filesystem::remove(file);
  CHECK_THROWS_WITH(report_for(file, 0.01),
                    Catch::Contains("initial[0].file.path: cannot read the particles of " + file +
                                    ": cannot open HDF5 file '" + file + "': no such file"));
  // The run's own snapshot: a fresh run empties out/r/particles/ first.
  const std::string own = (std::filesystem::absolute("out/r/particles") / "step_000004.h5").string();
  CHECK_THROWS_WITH(report_for(own, 0.01),
                    Catch::Contains("which a fresh run into out/r empties before it starts"));
}

TEST_CASE("an initial file whose particles lie outside the box is bad input", "[report]") {
  const std::string file =
      (std::filesystem::temp_directory_path() / ("coflow-outside-" + std::to_string(::getpid()) + ".h5"))
          .string();
  // A snapshot of a box twice as long in x: the third grain at x = 0.15 m.
  const std::vector<std::int64_t> id{0, 1, 2};
  const std::vector<std::int32_t> species{0, 0, 0};
  const std::vector<double> x{0.02, 0.02, 0.02, 0.05, 0.05, 0.05, 0.15, 0.08, 0.08}, zero(9, 0.0);
  const std::vector<double> radius{0.005, 0.005, 0.005};
  output::write_points(
      MPI_COMM_SELF, file, 0.0, 0, 3, id, species,
      {{"position", 3, x}, {"velocity", 3, zero}, {"angular_velocity", 3, zero}, {"radius", 1, radius}});
  CHECK_THROWS_WITH(
      report_for(file, 0.01),
      Catch::Contains("particles.initial[0].file.path: 1 of the 3 particles of " + file) &&
          Catch::Contains("lie outside the domain ((0, 0, 0) to (0.1, 0.1, 0.1)), e.g. particle 2 at "
                          "(0.15, 0.08, 0.08)"));
  std::filesystem::remove(file);
}

TEST_CASE("an initial file without velocities, or whose datasets' lengths disagree, is bad input",
          "[report]") {
  const std::string file =
      (std::filesystem::temp_directory_path() / ("coflow-shape-" + std::to_string(::getpid()) + ".h5"))
          .string();
  const std::vector<std::int64_t> id{0, 1};
  const std::vector<std::int32_t> species{0, 0};
  const std::vector<double> x{0.02, 0.02, 0.02, 0.05, 0.05, 0.05}, zero(6, 0.0), radius{0.005, 0.005};
  // No angular velocities: the particles read them at the start (before
  // 2026-12-07 validate did not, and the run stopped after its ranks began).
  output::write_points(MPI_COMM_SELF, file, 0.0, 0, 2, id, species,
                       {{"position", 3, x}, {"velocity", 3, zero}, {"radius", 1, radius}});
  CHECK_THROWS_WITH(report_for(file, 0.01),
                    Catch::Contains("initial[0].file.path: cannot read the particles of " + file) &&
                        Catch::Contains("angular_velocity"));
  std::filesystem::remove(file);
  // Lengths that disagree (the particles indexed the arrays by the radii's
  // count, past the end of a shorter one).
  CHECK(particles::snapshot_shape_error(2, 6, 6, 6, 2).empty());
  CHECK(particles::snapshot_shape_error(2, 3, 6, 6, 2) ==
        "its dataset position holds 3 values, but 2 radii need 6 (three a particle)");
  CHECK(particles::snapshot_shape_error(2, 6, 6, 4, 2) ==
        "its dataset angular_velocity holds 4 values, but 2 radii need 6 (three a particle)");
  CHECK(particles::snapshot_shape_error(2, 6, 6, 6, 1) ==
        "its dataset species holds 1 values, but there are 2 radii (one a particle)");
}
