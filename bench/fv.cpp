// Benchmark: the finite-volume fluid (fv), 1 rank, lid-driven cavity at
// Re = 1000 (U = 1 m/s, L = 1 m, nu = 1e-3 m^2/s) from rest.
//
//   build/bin/bench-fv [steps] [--quick] [--channel] [--cavity]
//
// (a) 2D at 128^2, 256^2 and 512^2: time per step and per cell, the pressure
//     Poisson's iterations and time per solve (relative tolerance 1e-10): the
//     iterations stay flat and the time per cell of a solve stays flat (O(N)).
// (b) 3D at 128^3 (--quick: 64^3).
// In (a) and (b) fv's Poisson runs by its geometric multigrid (the default),
// and again, in the same run, by hypre's PCG + PFMG (fluid.fv.multigrid: pfmg).
// Each case runs through OpenFOAM's icoFoam (Debian package openfoam,
// `icoFoam` on PATH) on the same grid with the same step (Courant 0.5 at the
// lid) and the same tolerance (p: GAMG, U: symmetric Gauss-Seidel, both to a
// residual of 1e-10; PISO with 2 correctors; Euler in time, Gauss linear in
// space), in the same run. Both start from rest; the first `steps` steps warm
// up, the next `steps` are timed.
//
// (c) k-epsilon: a 2D channel from an inlet at 256 x 64 and 512 x 128 (--quick:
//     the first): fv's k-epsilon step against its laminar step (the model's
//     cost; the two solvers step in turns, a fifth of the timed steps at a
//     time, so that the host's drift falls on both), with the seed's
//     two-layer model and with wall functions (wall: log-law, each against
//     a laminar run of its own), and against OpenFOAM's pimpleFoam with
//     kEpsilon (same grid, step and tolerances; OpenFOAM's walls take wall
//     functions, so its like is fv's log-law step). --channel: (c) alone;
//     --cavity: (a) and (b) alone.
//
// Last line: RESULT fv_s_per_step=... icofoam_s_per_step=... ratio=... (the
// 2D cavity at 512^2, or at 256^2 with --quick)
// k_epsilon_cost=... k_epsilon_vs_pimplefoam=... k_epsilon_log_law_cost=...
// k_epsilon_log_law_vs_pimplefoam=... (the largest channel; the first two
// the two-layer model's).
#include <fmt/format.h>
#include <mpi.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "bench_args.hpp"
#include "coflow/catalog.hpp"
#include "coflow/log.hpp"
#include "fluid/driver.hpp"
#include "fluid/fv/fv_solver.hpp"

using namespace coflow;

namespace {

struct Result {
  double s_per_step = 0.0, poisson_iterations = 0.0, poisson_s = 0.0, viscous_share = 0.0,
         poisson_share = 0.0;
  long cells = 0;
};

std::string cavity_yaml(int n, int dims, double dt, const std::string& multigrid) {
  const double dz = dims == 2 ? 1.0 / n : 1.0;
  return fmt::format(R"(
run: {{name: bench-fv, end_time: 1.0}}
domain: {{lower: [0, 0, 0], upper: [1, 1, {dz:.9g}], cells: [{n}, {n}, {nz}], periodic: [false, false, false]}}
fluid:
  solver: fv
  density: 1.0
  viscosity: 1.0e-3
  boundaries:
    y+: {{type: velocity, value: [1.0, 0.0, 0.0]}}
  fv: {{advection: central, time: sbdf2, cfl: 1.0, max_step: {dt:.17g}, tolerance: 1.0e-10, multigrid: {mg}}}
)",
                     fmt::arg("dz", dz), fmt::arg("n", n), fmt::arg("nz", dims == 2 ? 1 : n),
                     fmt::arg("dt", dt), fmt::arg("mg", multigrid));
}

Result run_fv_yaml(const std::string& yaml, double dt, long steps) {
  const config::Config cfg = config::parse_config_node(YAML::Load(yaml), "bench-fv", catalog());
  const fluid::FluidParams fp = fluid::read_params(cfg);
  const auto& c = cfg.domain.cells;
  const auto solver =
      fluid::make_solver({cfg, fp, coupler::Decomposition({c[0], c[1], c[2]}, 1), 0, MPI_COMM_WORLD});
  auto& fv = dynamic_cast<fluid::FvSolver&>(*solver);
  fv.advance(steps * dt);  // warm-up: the vortex forms
  const auto w0 = fv.work();
  fv.advance(steps * dt);
  const auto w1 = fv.work();
  Result res;
  const double s = w1.step_s - w0.step_s;
  const long k = w1.steps - w0.steps, solves = w1.poisson_solves - w0.poisson_solves;
  res.cells = long(c[0]) * c[1] * c[2];
  res.s_per_step = s / double(k);
  res.poisson_iterations = double(w1.poisson_iterations - w0.poisson_iterations) / double(solves);
  res.poisson_s = (w1.poisson_s - w0.poisson_s) / double(solves);
  res.poisson_share = (w1.poisson_s - w0.poisson_s) / s;
  res.viscous_share = (w1.viscous_s - w0.viscous_s) / s;
  return res;
}

Result run_fv(int n, int dims, double dt, long steps, const std::string& multigrid) {
  return run_fv_yaml(cavity_yaml(n, dims, dt, multigrid), dt, steps);
}

// (c) A 2D channel 8 x 2 (half height 1) from a uniform inlet (U = 1 m/s,
// nu = 1e-4 m^2/s: Re_b = 20000; k 3.75e-3, epsilon 2.69e-4) to a pressure
// face, walls at y- and y+; laminar (wall null) or with k-epsilon and that
// wall treatment (two-layer, log-law).
std::string channel_yaml(int nx, int ny, double dt, const char* wall) {
  std::string y = fmt::format(R"(
run: {{name: bench-fv-channel, end_time: 1.0}}
domain: {{lower: [0, 0, 0], upper: [8, 2, {dz:.9g}], cells: [{nx}, {ny}, 1], periodic: [false, false, false]}}
fluid:
  solver: fv
  density: 1.0
  viscosity: 1.0e-4
  initial: {{velocity: [1.0, 0.0, 0.0]}}
  boundaries:
    x-: {{type: velocity, value: [1.0, 0.0, 0.0]}}
    x+: {{type: pressure, value: 0.0}}
  fv: {{advection: upwind, time: sbdf2, cfl: 1.0, max_step: {dt:.17g}, tolerance: 1.0e-10}}
)",
                              fmt::arg("dz", 8.0 / nx), fmt::arg("nx", nx), fmt::arg("ny", ny), fmt::arg("dt", dt));
  if (wall)
    y += fmt::format(
        "  turbulence: {{model: k-epsilon, wall: {}, initial: {{k: 3.75e-3, epsilon: 2.69e-4}}, "
        "inlet: {{k: 3.75e-3, epsilon: 2.69e-4}}}}\n",
        wall);
  return y;
}

void write(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// The OpenFOAM case: the cavity as one block, the lid `movingWall`.
void write_openfoam_case(const std::filesystem::path& dir, int n, int dims, double dt, long steps) {
  const std::string head = "FoamFile { version 2.0; format ascii; class dictionary; object x; }\n";
  const double dz = dims == 2 ? 1.0 / n : 1.0;
  write(dir / "system/blockMeshDict",
        head + fmt::format(R"(convertToMeters 1;
vertices ((0 0 0) (1 0 0) (1 1 0) (0 1 0) (0 0 {dz:.9g}) (1 0 {dz:.9g}) (1 1 {dz:.9g}) (0 1 {dz:.9g}));
blocks (hex (0 1 2 3 4 5 6 7) ({n} {n} {nz}) simpleGrading (1 1 1));
boundary (
  movingWall {{ type wall; faces ((3 7 6 2)); }}
  fixedWalls {{ type wall; faces ((0 4 7 3) (2 6 5 1) (1 5 4 0)); }}
  frontAndBack {{ type {fb}; faces ((0 3 2 1) (4 5 6 7)); }}
);
)",
                           fmt::arg("dz", dz), fmt::arg("n", n), fmt::arg("nz", dims == 2 ? 1 : n),
                           fmt::arg("fb", dims == 2 ? "empty" : "wall")));
  const std::string fb = dims == 2 ? "empty" : "noSlip";
  const std::string fbp = dims == 2 ? "empty" : "zeroGradient";
  write(dir / "0/U",
        "FoamFile { version 2.0; format ascii; class volVectorField; object U; }\n"
        "dimensions [0 1 -1 0 0 0 0]; internalField uniform (0 0 0);\n"
        "boundaryField { movingWall { type fixedValue; value uniform (1 0 0); } fixedWalls { type "
        "noSlip; } frontAndBack { type " +
            fb + "; } }\n");
  write(dir / "0/p",
        "FoamFile { version 2.0; format ascii; class volScalarField; object p; }\n"
        "dimensions [0 2 -2 0 0 0 0]; internalField uniform 0;\n"
        "boundaryField { movingWall { type zeroGradient; } fixedWalls { type zeroGradient; } "
        "frontAndBack { type " +
            fbp + "; } }\n");
  write(dir / "constant/transportProperties", head + "nu 0.001;\n");
  write(dir / "system/controlDict",
        head + fmt::format("application icoFoam; startFrom startTime; startTime 0; stopAt endTime; endTime "
                           "{:.17g}; deltaT {:.17g}; writeControl timeStep; writeInterval 100000000; "
                           "purgeWrite 0; writeFormat binary; runTimeModifiable false;\n",
                           2 * steps * dt, dt));
  write(dir / "system/fvSchemes",
        head +
            "ddtSchemes { default Euler; } gradSchemes { default Gauss linear; } divSchemes { default none; "
            "div(phi,U) Gauss linear; } laplacianSchemes { default Gauss linear corrected; } "
            "interpolationSchemes { default linear; } snGradSchemes { default corrected; }\n");
  write(dir / "system/fvSolution",
        head +
            "solvers { p { solver GAMG; smoother GaussSeidel; tolerance 1e-10; relTol 0; } pFinal { $p; } "
            "U { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-10; relTol 0; } }\n"
            "PISO { nCorrectors 2; nNonOrthogonalCorrectors 0; pRefCell 0; pRefValue 0; }\n");
}

// The channel of (c) for pimpleFoam with OpenFOAM's kEpsilon (standard wall
// functions at the walls: OpenFOAM has no two-layer model), limitedLinear
// advection, PISO-mode PIMPLE (1 outer, 2 pressure correctors), every
// solve to 1e-10.
void write_pimple_case(const std::filesystem::path& dir, int nx, int ny, double dt, long steps) {
  const std::string head = "FoamFile { version 2.0; format ascii; class dictionary; object x; }\n";
  auto field = [](const char* cls, const char* name) {
    return fmt::format("FoamFile {{ version 2.0; format ascii; class {}; object {}; }}\n", cls, name);
  };
  const double dz = 8.0 / nx;
  write(dir / "system/blockMeshDict",
        head + fmt::format("convertToMeters 1;\nvertices ((0 0 0) (8 0 0) (8 2 0) (0 2 0) (0 0 {dz}) (8 0 {dz}) (8 2 "
                           "{dz}) (0 2 {dz}));\nblocks (hex (0 1 2 3 4 5 6 7) ({nx} {ny} 1) simpleGrading (1 1 1));\n"
                           "boundary ( inlet {{ type patch; faces ((0 4 7 3)); }} outlet {{ type patch; faces ((1 2 6 "
                           "5)); }} walls {{ type wall; faces ((0 1 5 4) (3 7 6 2)); }} frontAndBack {{ type empty; "
                           "faces ((0 3 2 1) (4 5 6 7)); }} );\n",
                           fmt::arg("dz", dz), fmt::arg("nx", nx), fmt::arg("ny", ny)));
  auto scalar = [&](const char* name, const char* dims, const std::string& value, const char* wall) {
    write(dir / "0" / name,
          field("volScalarField", name) +
              fmt::format("dimensions {}; internalField uniform {};\nboundaryField {{ inlet {{ type {}; value uniform "
                          "{}; }} outlet {{ type {}; value uniform {}; }} walls {{ type {}; value uniform {}; }} "
                          "frontAndBack {{ type empty; }} }}\n",
                          dims, value, std::string(name) == "nut" ? "calculated" : "fixedValue", value,
                          std::string(name) == "nut" ? "calculated" : "zeroGradient", value, wall, value));
  };
  write(dir / "0/U", field("volVectorField", "U") +
                         "dimensions [0 1 -1 0 0 0 0]; internalField uniform (1 0 0);\nboundaryField { inlet { type "
                         "fixedValue; value uniform (1 0 0); } outlet { type zeroGradient; } walls { type noSlip; } "
                         "frontAndBack { type empty; } }\n");
  write(dir / "0/p", field("volScalarField", "p") +
                         "dimensions [0 2 -2 0 0 0 0]; internalField uniform 0;\nboundaryField { inlet { type "
                         "zeroGradient; } outlet { type fixedValue; value uniform 0; } walls { type zeroGradient; } "
                         "frontAndBack { type empty; } }\n");
  scalar("k", "[0 2 -2 0 0 0 0]", "3.75e-3", "kqRWallFunction");
  scalar("epsilon", "[0 2 -3 0 0 0 0]", "2.69e-4", "epsilonWallFunction");
  scalar("nut", "[0 2 -1 0 0 0 0]", "0", "nutkWallFunction");
  write(dir / "constant/transportProperties", head + "transportModel Newtonian; nu 1e-4;\n");
  write(dir / "constant/turbulenceProperties",
        head + "simulationType RAS; RAS { RASModel kEpsilon; turbulence on; printCoeffs off; }\n");
  write(dir / "system/controlDict",
        head + fmt::format("application pimpleFoam; startFrom startTime; startTime 0; stopAt endTime; endTime "
                           "{:.17g}; deltaT {:.17g}; writeControl timeStep; writeInterval 100000000; "
                           "purgeWrite 0; writeFormat binary; runTimeModifiable false;\n",
                           2 * steps * dt, dt));
  write(dir / "system/fvSchemes",
        head + "ddtSchemes { default Euler; } gradSchemes { default Gauss linear; } divSchemes { default none; "
               "div(phi,U) Gauss limitedLinearV 1; div(phi,k) Gauss limitedLinear 1; div(phi,epsilon) Gauss "
               "limitedLinear 1; div((nuEff*dev2(T(grad(U))))) Gauss linear; } laplacianSchemes { default Gauss "
               "linear corrected; } interpolationSchemes { default linear; } snGradSchemes { default corrected; } "
               "wallDist { method meshWave; }\n");
  write(dir / "system/fvSolution",
        head + "solvers { p { solver GAMG; smoother GaussSeidel; tolerance 1e-10; relTol 0; } pFinal { $p; } "
               "\"(U|k|epsilon)\" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-10; relTol 0; } "
               "\"(U|k|epsilon)Final\" { $U; } }\nPIMPLE { nOuterCorrectors 1; nCorrectors 2; "
               "nNonOrthogonalCorrectors 0; pRefCell 0; pRefValue 0; }\n");
}

// icoFoam's seconds per step over the timed steps (ExecutionTime after step
// `steps` and after step 2 steps); 0 and a note when it is not there or fails.
template <class Writer>
double run_openfoam(const std::string& app, const std::string& tag, Writer&& write_case, long steps,
                    std::string& note) {
  if (std::system(fmt::format("command -v {} >/dev/null 2>&1", app).c_str()) != 0) {
    note = app + " not found (Debian package openfoam; scripts/setup installs it)";
    return 0.0;
  }
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("coflow-bench-fv-{}-{}", ::getpid(), tag);
  write_case(dir);
  // Debian's OpenFOAM finds its etc/ through WM_PROJECT_DIR.
  const std::string cmd = fmt::format(
      "cd '{}' && export WM_PROJECT_DIR=${{WM_PROJECT_DIR:-/usr/share/openfoam}} OMP_NUM_THREADS=1 && "
      "blockMesh > blockMesh.log 2>&1 && {} > solver.log 2>&1",
      dir.string(), app);
  const int rc = std::system(cmd.c_str());
  std::ifstream in(dir / "solver.log");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!std::getenv("COFLOW_BENCH_KEEP")) std::filesystem::remove_all(dir);
  const std::regex exec(R"(ExecutionTime = ([0-9.eE+-]+) s)");
  std::vector<double> times;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), exec); it != std::sregex_iterator(); ++it)
    times.push_back(std::stod((*it)[1]));
  if (rc != 0 || long(times.size()) < 2 * steps) {
    note = fmt::format("{} failed (exit {}); its log ends: {}", app, rc,
                       text.substr(text.size() > 400 ? text.size() - 400 : 0));
    return 0.0;
  }
  return (times[std::size_t(2 * steps - 1)] - times[std::size_t(steps - 1)]) / double(steps);
}

void report(const char* name, int n, int dims, long steps, Result& fv, double& foam) {
  const double dt = 0.5 / n;  // Courant 0.5 at the lid
  fv = run_fv(n, dims, dt, steps, "geometric");
  const Result pfmg = run_fv(n, dims, dt, steps, "pfmg");
  std::string note;
  foam = run_openfoam(
      "icoFoam", std::to_string(n), [&](const auto& dir) { write_openfoam_case(dir, n, dims, dt, steps); }, steps,
      note);
  std::printf(
      "%s %d^%d: fv %.4f s/step (%.1f ns per cell), Poisson %.1f iterations, %.4f s per solve "
      "(%.1f ns per cell), %.0f %% of the step (viscous %.0f %%)",
      name, n, dims, fv.s_per_step, 1e9 * fv.s_per_step / double(fv.cells), fv.poisson_iterations,
      fv.poisson_s, 1e9 * fv.poisson_s / double(fv.cells), 100 * fv.poisson_share, 100 * fv.viscous_share);
  std::printf("; with hypre's PCG + PFMG instead: Poisson %.1f iterations, %.4f s per solve, %.0f %% of its step "
              "(the geometric multigrid %.2fx faster per solve)",
              pfmg.poisson_iterations, pfmg.poisson_s, 100 * pfmg.poisson_share, pfmg.poisson_s / fv.poisson_s);
  if (foam > 0)
    std::printf("; icoFoam %.4f s/step: fv %.2fx faster\n", foam, foam / fv.s_per_step);
  else
    std::printf("; %s\n", note.c_str());
  std::fflush(stdout);
}

// fv's s/step for two configurations on the same grid and step, timed in
// turns: both warm up `steps` steps, then each runs `steps` more in chunks of
// a fifth, alternating, so that the host's drift (tens of per cent over
// seconds) falls on both alike.
std::pair<double, double> run_fv_pair(const std::string& yaml_a, const std::string& yaml_b, double dt,
                                      long steps) {
  auto make = [](const std::string& yaml) {
    const config::Config cfg = config::parse_config_node(YAML::Load(yaml), "bench-fv", catalog());
    const fluid::FluidParams fp = fluid::read_params(cfg);
    const auto& c = cfg.domain.cells;
    return fluid::make_solver({cfg, fp, coupler::Decomposition({c[0], c[1], c[2]}, 1), 0, MPI_COMM_WORLD});
  };
  const auto a = make(yaml_a), b = make(yaml_b);
  auto& fa = dynamic_cast<fluid::FvSolver&>(*a);
  auto& fb = dynamic_cast<fluid::FvSolver&>(*b);
  fa.advance(steps * dt);
  fb.advance(steps * dt);
  const auto a0 = fa.work(), b0 = fb.work();
  const long chunk = std::max(1L, steps / 5);
  for (long done = 0; done < steps; done += chunk) {
    fa.advance(chunk * dt);
    fb.advance(chunk * dt);
  }
  const auto a1 = fa.work(), b1 = fb.work();
  return {(a1.step_s - a0.step_s) / double(a1.steps - a0.steps),
          (b1.step_s - b0.step_s) / double(b1.steps - b0.steps)};
}

// (c): fv with k-epsilon against fv laminar (the cost of the model, timed in
// turns), with the two-layer model and with wall functions, and against
// pimpleFoam with kEpsilon, same grid, step and tolerances. ratio_laminar,
// ratio_foam: the two-layer model's, then the log-law's.
void report_channel(int nx, int ny, long steps, std::array<double, 2>& ratio_laminar,
                    std::array<double, 2>& ratio_foam) {
  const double dt = 0.4 * 8.0 / nx;  // Courant about 0.5 at the channel's core
  std::string note;
  const double foam = run_openfoam(
      "pimpleFoam", fmt::format("ke{}", nx), [&](const auto& dir) { write_pimple_case(dir, nx, ny, dt, steps); },
      steps, note);
  std::printf("(c) channel %dx%d:", nx, ny);
  const char* walls[2] = {"two-layer", "log-law"};
  for (std::size_t w = 0; w < 2; ++w) {
    const auto [lam, ke] =
        run_fv_pair(channel_yaml(nx, ny, dt, nullptr), channel_yaml(nx, ny, dt, walls[w]), dt, steps);
    ratio_laminar[w] = ke / lam;
    ratio_foam[w] = foam > 0 ? foam / ke : std::nan("");
    std::printf(
        "%s fv laminar %.4f s/step, fv k-epsilon (%s) %.4f s/step (%.2fx the laminar step, timed in turns)",
        w ? ";" : "", lam, walls[w], ke, ratio_laminar[w]);
    if (foam > 0) std::printf(", pimpleFoam kEpsilon %.4f s/step: fv %.2fx faster", foam, ratio_foam[w]);
  }
  if (foam <= 0) std::printf("; %s", note.c_str());
  std::printf("\n");
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  long steps = 20;
  bool quick = false, channel_only = false, cavity_only = false;
  CLI::App app{"bench-fv: the fv fluid against OpenFOAM (see bench/fv.cpp)"};
  coflow::bench::add_steps(app, steps, "warm-up steps, then as many timed");
  app.add_flag("--quick", quick, "the smaller grids only (2D to 256^2, 3D 64^3, the first channel)");
  auto* channel = app.add_flag("--channel", channel_only, "(c) the k-epsilon channel alone");
  app.add_flag("--cavity", cavity_only, "(a) and (b) the cavities alone")->excludes(channel);
  coflow::bench::parse_args(app, argc, argv);
  MPI_Init(&argc, &argv);
  log::init("bench", 1);  // rank 1: warnings only
  std::printf(
      "bench-fv: 1 rank, lid-driven cavity Re 1000, %ld warm-up + %ld timed steps per 2D case (3D: %ld + "
      "%ld)\n",
      steps, steps, std::max(2L, steps / 5), std::max(2L, steps / 5));
  Result fv;
  double foam = 0.0, fv512 = 0.0, foam512 = 0.0;
  for (int n : {128, 256, 512}) {
    if ((quick && n > 256) || channel_only) break;
    report("(a) 2D", n, 2, steps, fv, foam);
    fv512 = fv.s_per_step;
    foam512 = foam;
  }
  if (!channel_only) report("(b) 3D", quick ? 64 : 128, 3, std::max(2L, steps / 5), fv, foam);
  std::array<double, 2> ke_cost{}, ke_vs_foam{};
  for (int nx : {256, 512}) {
    if ((quick && nx > 256) || cavity_only) break;
    report_channel(nx, nx / 4, steps, ke_cost, ke_vs_foam);
  }
  std::printf(
      "RESULT fv_s_per_step=%.4g icofoam_s_per_step=%.4g ratio=%.3f k_epsilon_cost=%.3f "
      "k_epsilon_vs_pimplefoam=%.3f k_epsilon_log_law_cost=%.3f k_epsilon_log_law_vs_pimplefoam=%.3f (%s)\n",
      fv512, foam512, foam512 > 0 ? foam512 / fv512 : std::nan(""), ke_cost[0], ke_vs_foam[0], ke_cost[1],
      ke_vs_foam[1], quick ? "the 2D cavity at 256^2: --quick" : "the 2D cavity at 512^2");
  MPI_Finalize();
  return 0;
}
