// Benchmark: fv's adaptive grid (fluid/fv/amr) against the same solver on
// the uniform grid of its finest level, in one run, 1 rank.
//
//   build/bin/bench-amr [steps] [--out DIR] [--configs DIR]
//
// The case: a periodic planar jet on [0, 2 pi]^2 (u = 1 in a band of half
// width pi/4 about y = pi, tanh edges of width pi/40; v a 5 % sin x
// perturbation; nu = 1e-3), whose two shear layers roll up into vortices.
// The adaptive run has 3 levels (4 x 4 trees of 8^2-cell patches: 32^2 to
// 128^2), refines where |omega| > 1, coarsens where it is below 0.3,
// regrids every 5 steps (vorticity, marks, p4est adapt and repartition,
// conservative transfer, operators rebuilt, a projection). The uniform run
// has every leaf on level 2 (128^2). Same step (CFL 0.3 on the finest
// cells), same number of steps.
//
// (b) then runs the cylinder of configs/validation/ibm_cylinder_amr.yaml
// (the issue's case) through the launcher, adaptive, adaptive with every leaf
// on the finest level and on fv's uniform grid, three times each, interleaved.
//
// (c) a viscous start-up: plane Poiseuille flow (Re 10, nu 0.1) from rest in
// a [0, 2] x [0, 1] channel with its wall trees one level finer (1280
// cells), inlet profile given, outlet p = 0, to t = 6: explicit diffusion at
// its limit (5000 steps of 0.0012) against implicit at steps of 0.02 (300),
// their wall times, ratio and largest |u - u_exact| (the steady profile).
//
// Prints, for each: cells, time per step (regrids apart), cells x steps per
// second; for the adaptive run the regrid's share of the wall time (target
// <= 10 %), the ratio of its cells per second to the uniform run's (target
// >= 0.7), its mean cells against the uniform count, and the enstrophy of
// both at the end (how much of the flow the adaptive grid keeps). With
// --out, writes DIR/amr_cells.csv (t, cells) and the last state of both runs,
// DIR/amr_jet.{h5,xmf} and DIR/uniform_jet.{h5,xmf} (ParaView opens the .xmf;
// scripts/plot_amr.py draws them).
#include <fmt/format.h>
#include <mpi.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "bench_args.hpp"
#include "bench_util.hpp"
#include "fluid/fv/amr/composite_flow.hpp"
#include "fluid/fv/amr/composite_output.hpp"
#include "fluid/fv/amr/refinement_criteria.hpp"
#include "text_file.hpp"

using namespace coflow::fluid::fv::amr;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Result {
  double step_s = 0.0, regrid_s = 0.0, mean_cells = 0.0, enstrophy = 0.0, iterations = 0.0;
  int regrids = 0;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void set_jet(Forest& forest, const CompositeGrid& g) {
  const double w = kPi / 4, delta = kPi / 40;
  for (long c = 0; c < g.local_cells(); ++c) {
    const auto x = g.centre(g.local_cell(c));
    auto v = forest.data(static_cast<std::size_t>(c / g.cells_per_patch()));
    const auto k = static_cast<std::size_t>(c % g.cells_per_patch()) * 4;
    v[k] = 0.5 * (std::tanh((x[1] - kPi + w) / delta) - std::tanh((x[1] - kPi - w) / delta));
    v[k + 1] = 0.05 * std::sin(x[0]);
  }
}

double enstrophy(CompositeFlow& flow, Forest& forest) {
  flow.vorticity(3);
  const auto& g = flow.grid();
  double e = 0.0;
  for (long c = 0; c < g.local_cells(); ++c) {
    const double w = forest.data(static_cast<std::size_t>(
        c / g.cells_per_patch()))[static_cast<std::size_t>(c % g.cells_per_patch()) * 4 + 3];
    e += 0.5 * w * w * std::pow(g.spacing(g.local_cell(c).level), 2);
  }
  MPI_Allreduce(MPI_IN_PLACE, &e, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return e;
}

Result run(bool adaptive, int steps, const std::string& out_dir) {
  ForestSpec spec;
  spec.dims = 2;
  spec.trees = {4, 4, 1};
  spec.periodic = {true, true, false};
  spec.patch = 8;
  spec.components = 4;  // u, v, p, |omega|
  spec.max_level = 2;
  spec.min_level = adaptive ? 0 : 2;
  Forest forest(MPI_COMM_WORLD, spec);
  CompositeFlow flow(forest, {{0.0, 0.0, 0.0}, 0.5 * kPi}, 1e-3);
  const auto marks = [&] {
    flow.vorticity(3);
    return mark_by_magnitude(forest, 3, 1.0, 0.3);
  };
  for (int pass = 0; adaptive && pass < 2; ++pass) {
    set_jet(forest, flow.grid());
    flow.regrid(marks());
  }
  set_jet(forest, flow.grid());
  flow.project_initial();
  const double dt = 0.3 * flow.grid().spacing(2);
  std::ofstream cells_csv;
  if (adaptive && !out_dir.empty()) {
    cells_csv.open(out_dir + "/amr_cells.csv");
    cells_csv << "t,cells\n0," << flow.grid().global_cells() << "\n";
  }
  Result r;
  double cell_steps = 0.0;
  for (int n = 1; n <= steps; ++n) {
    auto t0 = std::chrono::steady_clock::now();
    flow.step(dt);
    r.step_s += seconds_since(t0);
    r.iterations += flow.last_iterations() / static_cast<double>(steps);
    cell_steps += static_cast<double>(flow.grid().global_cells());
    if (adaptive && n % 5 == 0) {
      t0 = std::chrono::steady_clock::now();
      flow.regrid(marks());
      r.regrid_s += seconds_since(t0);
      ++r.regrids;
      if (cells_csv) cells_csv << n * dt << "," << flow.grid().global_cells() << "\n";
    }
  }
  r.mean_cells = cell_steps / steps;
  r.enstrophy = enstrophy(flow, forest);
  if (!out_dir.empty())  // the vorticity is current (enstrophy)
    write_composite(flow.grid(), out_dir, adaptive ? "amr_jet" : "uniform_jet", steps * dt, steps,
                    {{"velocity", 0, 2}, {"pressure", 2, 1}, {"vorticity", 3, 1}});
  return r;
}

// (b) The cylinder of configs/validation/ibm_cylinder_amr.yaml (Re 20 in a
// 16 x 16 box, 3 levels, the finest 128^2 around the body and its wake; an
// immersed boundary, so three executables) through the launcher, and the
// same case on fv's uniform grid of the finest level (fluid.fv.refinement:
// null) and on the adaptive code with every leaf on the finest level
// (ibm_cylinder_amr_fine.yaml), three times each, interleaved (this host's
// speed drifts by tens of per cent between runs): the medians. Reads the
// fluids' logs: the adaptive solver's steps, regrids and cells, fv's steps.
struct CylinderRun {
  double step_s = 0, rate = 0, regrid_pct = 0, cells = 0;
};

// One run's figures from its fluid log, or false when it logged none.
bool parse_cylinder(const std::string& log, double uniform_cells, CylinderRun& r) {
  static const std::regex amr_line(
      R"(fv \(refinement\): (\d+) steps in ([0-9.]+) s, (\d+) regrids in ([0-9.]+) s)"
      R"( \(([0-9.]+) % of both\); (\d+) cells on average, ([0-9.eE+-]+) cell-steps per second)");
  static const std::regex fv_line(R"(fv: (\d+) steps in ([0-9.]+) s)");
  std::smatch m;
  if (std::regex_search(log, m, amr_line)) {
    r = {(std::stod(m[2]) + std::stod(m[4])) / std::stod(m[1]), std::stod(m[7]), std::stod(m[5]),
         std::stod(m[6])};
    return true;
  }
  if (!std::regex_search(log, m, fv_line)) return false;
  r = {std::stod(m[2]) / std::stod(m[1]), uniform_cells * std::stod(m[1]) / std::stod(m[2]), 0.0,
       uniform_cells};
  return true;
}

// Returns the report ("" when a run fails). Runs before MPI_Init: the
// launcher's mpirun must not start inside this MPI process.
std::string cylinder(const std::filesystem::path& bin, const std::filesystem::path& config) {
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("coflow-bench-amr-{}", ::getpid());
  const auto run_case = [&](const std::string& name, const std::filesystem::path& file, const std::string& sets) {
    const auto out = dir / name;
    const std::string cmd = fmt::format("'{}' run '{}' --set run.output.dir='{}' {} > '{}.log' 2>&1",
                                        (bin / "coflow").string(), file.string(), out.string(), sets, out.string());
    if (std::system(cmd.c_str()) != 0) return std::string();
    return coflow::bench::slurp((out / "logs" / "fluid.log").string());
  };
  std::filesystem::create_directories(dir);
  const auto fine_config =
      config.parent_path() / "ibm_cylinder_amr_fine.yaml";  // every leaf on the finest level
  const auto cells = YAML::LoadFile(config.string())["domain"]["cells"];
  const double uniform_cells = cells[0].as<double>() * cells[1].as<double>() * cells[2].as<double>();
  std::vector<double> amr_step, amr_rate, share, fine_rate, uni_step, uni_rate, vs_fine, vs_fv, wall_vs_fv;
  double amr_cells = 0.0;  // the mean cells, the same each run
  for (int rep = 0; rep < 3; ++rep) {
    CylinderRun a, f, u;
    if (!parse_cylinder(run_case("amr", config, ""), uniform_cells, a) ||
        !parse_cylinder(run_case("fine", fine_config, ""), uniform_cells, f) ||
        !parse_cylinder(run_case("uniform", config, "--set fluid.fv.refinement=null"), uniform_cells, u)) {
      fmt::print("(b) cylinder: a run failed or logged no timing (COFLOW_BENCH_KEEP=1 keeps {})\n",
                 dir.string());
      return "";
    }
    amr_step.push_back(a.step_s), amr_rate.push_back(a.rate), share.push_back(a.regrid_pct);
    fine_rate.push_back(f.rate), uni_step.push_back(u.step_s), uni_rate.push_back(u.rate);
    vs_fine.push_back(a.rate / f.rate), vs_fv.push_back(a.rate / u.rate),
        wall_vs_fv.push_back(a.step_s / u.step_s);
    amr_cells = a.cells;
  }
  if (!std::getenv("COFLOW_BENCH_KEEP")) std::filesystem::remove_all(dir);
  using coflow::bench::median;
  std::string r =
      "(b) cylinder (ibm_cylinder_amr.yaml, 3 levels, coupled run, 1 fluid rank), medians of 3 "
      "interleaved runs:\n";
  r += fmt::format("  fv uniform {:.0f} cells: {:.4f} s/step, {:.3g} cells*steps/s\n", uniform_cells,
                   median(uni_step), median(uni_rate));
  r += fmt::format(
      "  adaptive {:.0f} cells on average ({:.0f} % fewer): {:.4f} s/step with regrids, regrids {:.1f} % "
      "of the time, {:.3g} cells*steps/s\n",
      amr_cells, 100.0 * (1.0 - amr_cells / uniform_cells), median(amr_step), median(share),
      median(amr_rate));
  r += fmt::format("  adaptive code with every leaf on the finest level: {:.3g} cells*steps/s\n",
                   median(fine_rate));
  r += fmt::format("  adaptive / every leaf finest, cells*steps/s, each run: {:.3f} {:.3f} {:.3f}\n",
                   vs_fine[0], vs_fine[1], vs_fine[2]);
  r += fmt::format(
      "RESULT cylinder_regrid_share={:.3f} cylinder_rate_ratio_fv={:.3f} cylinder_rate_ratio_fine={:.3f} "
      "cylinder_wall_ratio_fv={:.3f}\n",
      median(share) / 100.0, median(vs_fv), median(vs_fine), median(wall_vs_fv));
  return r;
}

}  // namespace

// (c): the channel to t = 6, diffusion explicit or implicit; the wall time
// of the steps and the largest |u - 6 y (1 - y)| at the end.
std::pair<double, double> startup(bool implicit) {
  ForestSpec spec;
  spec.dims = 2;
  spec.trees = {8, 4, 1};
  spec.periodic = {false, false, false};
  spec.patch = 4;
  spec.components = 3;
  spec.max_level = 1;
  spec.refine = [](int, const Index3& p) { return p[1] == 0 || p[1] == 3; };
  Forest forest(MPI_COMM_WORLD, spec);
  CompositeFlow flow(forest, {{0.0, 0.0, 0.0}, 0.25}, 0.1);
  flow.set_implicit_diffusion(implicit);
  const auto profile = [](const std::array<double, 3>& x) {
    return std::array<double, 3>{6 * x[1] * (1 - x[1]), 0, 0};
  };
  flow.set_inlet(0, profile);
  flow.set_outlet(1);
  flow.project_initial();
  const auto t0 = std::chrono::steady_clock::now();
  const int steps = implicit ? 300 : 5000;
  for (int n = 0; n < steps; ++n) flow.step(6.0 / steps);
  const double wall = seconds_since(t0);
  const auto& g = flow.grid();
  double worst = 0.0;
  for (long c = 0; c < g.local_cells(); ++c) {
    const auto v = forest.data(static_cast<std::size_t>(c / g.cells_per_patch()));
    const double u = v[static_cast<std::size_t>(c % g.cells_per_patch()) * 3];
    worst = std::max(worst, std::abs(u - profile(g.centre(g.local_cell(c)))[0]));
  }
  return {wall, worst};
}

int main(int argc, char** argv) {
  // The launcher beside this program (build/bin); the configs two levels up,
  // or where --configs DIR says.
  const auto bin = std::filesystem::canonical("/proc/self/exe").parent_path();
  std::string configs = (bin.parent_path().parent_path() / "configs").string();
  int steps = 500;
  std::string out_dir;
  CLI::App app{"bench-amr: fv's adaptive grid against its uniform finest grid (see bench/amr.cpp)"};
  coflow::bench::add_steps(app, steps, "steps of the jet");
  app.add_option("--out", out_dir, "write the jet's cells and last states here");
  app.add_option("--configs", configs, "the configs directory")
      ->check(CLI::ExistingDirectory)
      ->capture_default_str();
  coflow::bench::parse_args(app, argc, argv);
  const auto config = std::filesystem::path(configs) / "validation" / "ibm_cylinder_amr.yaml";
  const std::string cylinder_report = std::filesystem::exists(config)
                                          ? cylinder(bin, config)
                                          : fmt::format("(b) cylinder: {} not found\n", config.string());
  MPI_Init(&argc, &argv);
  if (!out_dir.empty()) std::filesystem::create_directories(out_dir);
  const auto uniform = run(false, steps, out_dir);
  const auto amr = run(true, steps, out_dir);
  const double uniform_rate = uniform.mean_cells * steps / uniform.step_s;
  const double amr_rate = amr.mean_cells * steps / (amr.step_s + amr.regrid_s);
  const double regrid_share = amr.regrid_s / (amr.step_s + amr.regrid_s);
  fmt::print("bench-amr: periodic planar jet, {} steps, 1 rank\n", steps);
  fmt::print(
      "  uniform  (level 2 everywhere): {:6.0f} cells, {:.4f} s/step, {:.3g} cells*steps/s, enstrophy "
      "{:.5g}, "
      "{:.1f} Poisson iterations\n",
      uniform.mean_cells, uniform.step_s / steps, uniform_rate, uniform.enstrophy, uniform.iterations);
  fmt::print("  adaptive Poisson iterations: {:.1f}\n", amr.iterations);
  fmt::print(
      "  adaptive (3 levels, regrid every 5): {:6.0f} cells on average ({:.0f} % fewer), {:.4f} s/step, "
      "regrid {:.4f} s each ({:.1f} % of the wall time), {:.3g} cells*steps/s, enstrophy {:.5g} ({:+.2f} "
      "%)\n",
      amr.mean_cells, 100.0 * (1.0 - amr.mean_cells / uniform.mean_cells), amr.step_s / steps,
      amr.regrid_s / std::max(1, amr.regrids), 100.0 * regrid_share, amr_rate, amr.enstrophy,
      100.0 * (amr.enstrophy / uniform.enstrophy - 1.0));
  fmt::print(
      "RESULT cells_ratio={:.3f} rate_ratio={:.3f} regrid_share={:.3f} wall_ratio={:.3f} "
      "enstrophy_diff={:.4f}\n",
      amr.mean_cells / uniform.mean_cells, amr_rate / uniform_rate, regrid_share,
      (amr.step_s + amr.regrid_s) / uniform.step_s, amr.enstrophy / uniform.enstrophy - 1.0);
  fmt::print("{}", cylinder_report);
  const auto [explicit_s, explicit_error] = startup(false);
  const auto [implicit_s, implicit_error] = startup(true);
  fmt::print(
      "(c) channel start-up to t = 6 (1280 cells, nu 0.1): explicit 5000 steps {:.2f} s (|u - u_exact| "
      "{:.4f}), implicit 300 steps {:.2f} s ({:.4f})\nRESULT startup_wall_ratio={:.2f}\n",
      explicit_s, explicit_error, implicit_s, implicit_error, explicit_s / implicit_s);
  MPI_Finalize();
  return cylinder_report.rfind("RESULT") != std::string::npos ? 0 : 1;
}
