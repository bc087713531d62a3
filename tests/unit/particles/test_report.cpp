// The particles' part of the pre-run report: an initial file whose radii
// differ from the species' diameter is a warning that counts them; the same
// file with matching radii is not.
#include <mpi.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "coflow/catalog.hpp"
#include "coflow/output.hpp"
#include "coflow/report.hpp"
#include "coflow/run_config.hpp"

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
  const config::Report r = report_for(file, 0.01);
  REQUIRE(r.warnings.size() == 1);
  CHECK_THAT(r.warnings[0], Catch::Contains("1 of the 3 particles") && Catch::Contains("diameter 0.012 m") &&
                                Catch::Contains("species 'grain' says 0.01 m"));
  CHECK(report_for(file, 0.012).warnings.size() == 1);  // now the two others differ
  CHECK_THAT(report_for(file, 0.012).warnings[0], Catch::Contains("2 of the 3 particles"));
  std::filesystem::remove(file);
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
      Catch::Contains("particles.initial: item 0: 1 of the 3 particles of " + file) &&
          Catch::Contains("lie outside the domain ((0, 0, 0) to (0.1, 0.1, 0.1)), e.g. particle 2 at "
                          "(0.15, 0.08, 0.08)"));
  std::filesystem::remove(file);
}
