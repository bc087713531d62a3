// Benchmark: the immersed boundary's cost in a coupled run (issue 23).
//
//   build/bin/bench-ibm [CELLS] [PLATE.stl]
//
// The plate of seed 003 §5.3 (configs/cases/geometry/jet_plate.stl: 0.1 m x
// 0.1 m x 2 mm, 104 972 triangles, normal y, centre (0.1, 0.05, 0.1)) in a
// 0.2 m cube of CELLS^3 fv cells (default 128), air (rho 1.2 kg/m^3, nu 1.5e-5
// m^2/s) coming at 1 m/s through y+ and leaving through y-, symmetry faces
// around; 5 windows of 2 ms, through the launcher (fluid and immersed, one
// rank each). Fixed, and moving (a translation of 1 cm/s: the markers go to
// the fluid every window). From the run's logs, series and summary.json it
// prints the markers, the forcing iterations, the immersed boundary's share of
// the fluid's steps (stencils, iterations, their reductions: fv's own timer),
// and the exchange share: the time the fluid spent in its exchanges with
// immersed (sending loads, receiving markers, waiting for them) over its wall
// time, with the bytes moved.
//
// Last line: RESULT markers=... iterations=... ibm_pct=... exchange_pct=... (fixed)
// moving_ibm_pct=... moving_exchange_pct=...
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "bench_args.hpp"
#include "text_file.hpp"

namespace {

struct Figures {
  long markers = 0;
  double iterations = 0, ibm_pct = 0, exchange_pct = 0, wall = 0, mb = 0, fluid_s_per_step = 0;
};

double match(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) throw std::runtime_error("not found in a log: " + pattern);
  return std::stod(m[1]);
}

std::string config(int cells, const std::string& plate, bool moving) {
  return fmt::format(R"(run: {{name: bench-ibm, end_time: 0.01, output: {{every: 0.01, series_every: 0.002, fields: [velocity]}}}}
coupling: {{window: 0.002}}
domain: {{lower: [0, 0, 0], upper: [0.2, 0.2, 0.2], cells: [{n}, {n}, {n}], periodic: [false, false, false]}}
fluid:
  solver: fv
  density: 1.2
  viscosity: 1.5e-5
  initial: {{velocity: [0.0, -1.0, 0.0]}}
  boundaries:
    x-: {{type: symmetry}}
    x+: {{type: symmetry}}
    y-: {{type: outflow}}
    y+: {{type: velocity, value: [0.0, -1.0, 0.0]}}
    z-: {{type: symmetry}}
    z+: {{type: symmetry}}
  fv: {{advection: upwind, cfl: 0.5, tolerance: 1.0e-8}}
immersed:
  method: ibm
  ibm:
    kernel: roma3
    bodies:
      - name: plate
        mesh: {plate}
        motion: {{velocity: [0.0, {v}, 0.0]}}
)",
                     fmt::arg("n", cells), fmt::arg("plate", plate), fmt::arg("v", moving ? 0.01 : 0.0));
}

Figures run(const std::string& coflow, int cells, const std::string& plate, bool moving) {
  const auto dir = std::filesystem::temp_directory_path() / (moving ? "coflow-bench-ibm-moving" : "coflow-bench-ibm");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "case.yaml") << config(cells, plate, moving);
  const std::string out = (dir / "out").string();
  const std::string cmd = fmt::format("'{}' run '{}' --set run.output.dir='{}' > '{}/run.log' 2>&1", coflow,
                                      (dir / "case.yaml").string(), out, dir.string());
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("run failed: see " + dir.string() + "/run.log");
  Figures f;
  const std::string fluid_log = coflow::bench::slurp(out + "/logs/fluid.log"),
                    immersed_log = coflow::bench::slurp(out + "/logs/immersed.log");
  f.markers = std::lround(match(immersed_log, R"(ibm: (\d+) markers)"));
  f.ibm_pct = match(fluid_log, R"(immersed boundary ([0-9.]+) %)");
  const double steps = match(fluid_log, R"(fv: (\d+) steps in)"), step_s = match(fluid_log, R"(steps in ([0-9.]+) s)");
  f.fluid_s_per_step = step_s / steps;
  const YAML::Node s = YAML::LoadFile(out + "/summary.json");  // JSON is YAML
  const auto& fl = s["components"]["fluid"];
  f.wall = fl["wall_s"].as<double>();
  f.exchange_pct = 100 * (fl["exchange_s"].as<double>() + fl["wait_s"].as<double>()) / f.wall;
  f.mb = (fl["bytes_received"].as<double>() + fl["bytes_sent"].as<double>()) / 1e6;
  std::ifstream series(out + "/series/immersed.csv");
  std::string line, last;
  while (std::getline(series, line)) last = line;
  f.iterations = std::stod(last.substr(last.find_last_of(',', last.find_last_of(',') - 1) + 1));
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    int cells = 128;
    std::string plate_file = "configs/cases/geometry/jet_plate.stl";
    CLI::App app{"bench-ibm: the immersed boundary's cost in a coupled run (see bench/ibm.cpp)"};
    app.add_option("cells", cells, "fv cells along each axis")
        ->check(CLI::Range(8, 1024))
        ->capture_default_str();
    app.add_option("plate", plate_file, "the plate's STL")->check(CLI::ExistingFile)->capture_default_str();
    coflow::bench::parse_args(app, argc, argv);
    const std::string plate = std::filesystem::absolute(plate_file);
    const std::string coflow =
        (std::filesystem::canonical("/proc/self/exe").parent_path() / "coflow").string();
    std::printf("bench-ibm: the jet plate (%s) in %d^3 fv cells, 5 windows of 2 ms\n", plate.c_str(), cells);
    const Figures fixed = run(coflow, cells, plate, false), moving = run(coflow, cells, plate, true);
    for (const auto& [name, f] : {std::pair{"fixed", fixed}, std::pair{"moving", moving}})
      std::printf("%-7s markers %ld | fluid step %.3f s | forcing iterations (last window, most) %.0f | immersed "
                  "boundary %.1f %% of the fluid's steps | exchange and waiting %.2f %% of the fluid's wall "
                  "(%.2f MB moved)\n",
                  name, f.markers, f.fluid_s_per_step, f.iterations, f.ibm_pct, f.exchange_pct, f.mb);
    std::printf("RESULT markers=%ld iterations=%.0f ibm_pct=%.1f exchange_pct=%.2f moving_ibm_pct=%.1f "
                "moving_exchange_pct=%.2f\n",
                fixed.markers, fixed.iterations, fixed.ibm_pct, fixed.exchange_pct, moving.ibm_pct,
                moving.exchange_pct);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench-ibm: %s\n", e.what());
    return 1;
  }
  return 0;
}
