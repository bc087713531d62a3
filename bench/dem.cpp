// Benchmark: soft-sphere DEM, 1 rank, particle-steps per second (psps).
//
//   build/bin/bench-dem [steps]
//
// (a) dense: 40^3 = 64 000 monodisperse 1 mm spheres on a simple cubic lattice of
//     spacing 0.99 mm in a periodic box, so every sphere touches its 6
//     neighbours (overlap 10 um); friction 0.5; no gravity; 1000 steps.
//     The same case is run through LIGGGHTS 3.8 (`liggghts` on PATH, Debian
//     package liggghts) with `pair_style gran model hooke tangential history`,
//     `fix nve/sphere`, a bin neighbour list with a 0.1 mm skin, in the same run.
// (b) pour: 100 000 spheres of 0.8-1.2 mm at random in a box, falling under
//     gravity onto its floor; coflow only.
//
// Last line: RESULT coflow_psps=... liggghts_psps=... ratio=... (case a).
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
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "bench_args.hpp"
#include "coflow/catalog.hpp"
#include "coflow/log.hpp"
#include "coflow/output.hpp"
#include "particles/dem/dem_solver.hpp"

using namespace coflow;

namespace {

constexpr double kDensity = 2650.0, kDiameter = 1.0e-3, kSpacing = 0.99e-3, kFriction = 0.5;
constexpr int kSide = 40;  // lattice points per side: 64 000 spheres
constexpr double kStep = 1.0e-6;

struct Timing {
  long particles = 0;
  double seconds = 0.0;
  double psps(long steps) const { return seconds > 0 ? double(particles) * steps / seconds : 0.0; }
};

Timing run_coflow(const std::string& yaml, long steps) {
  const config::Config cfg = config::parse_config_node(YAML::Load(yaml), "bench-dem", catalog());
  particles::ParticleParams params;
  config::Reader r(cfg.resolved["particles"], "bench-dem", "particles");
  params.visit(r, cfg);
  const auto& c = cfg.domain.cells;
  particles::DemSolver dem({cfg, params, coupler::Decomposition({c[0], c[1], c[2]}, 1), 0, MPI_COMM_WORLD}, {});
  dem.step(kStep);  // warm-up: contact histories allocated
  const auto t0 = std::chrono::steady_clock::now();
  for (long n = 0; n < steps; ++n) dem.step(kStep);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {static_cast<long>(dem.particles().size()), s};
}

// Case (a) through LIGGGHTS; {0, 0} when liggghts is not available or fails.
Timing run_liggghts(long steps, std::string& note) {
  if (std::system("command -v liggghts >/dev/null 2>&1") != 0) {
    note = "liggghts not found (Debian package liggghts; scripts/setup installs it)";
    return {};
  }
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("coflow-bench-dem-{}", ::getpid());
  std::filesystem::create_directories(dir);
  const double L = kSide * kSpacing;
  std::ofstream(dir / "in.bench") << fmt::format(
      R"(# coflow bench-dem case (a): dense simple cubic lattice, every neighbour in contact
atom_style granular
atom_modify map array
boundary p p p
newton off
communicate single vel yes
units si
region box block 0 {L:.9g} 0 {L:.9g} 0 {L:.9g} units box
create_box 1 box
neighbor 1.0e-4 bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype 5.0e6
fix m2 all property/global poissonsRatio peratomtype 0.45
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.9
fix m4 all property/global coefficientFriction peratomtypepair 1 {mu}
fix m5 all property/global characteristicVelocity scalar 0.1
pair_style gran model hooke tangential history
pair_coeff * *
timestep {dt:.9g}
lattice sc {a:.9g}
create_atoms 1 box
set group all diameter {d:.9g} density {rho:.9g}
fix integr all nve/sphere
thermo 1000
run 1
run {steps}
)",
      fmt::arg("L", L), fmt::arg("mu", kFriction), fmt::arg("dt", kStep), fmt::arg("a", kSpacing),
      fmt::arg("d", kDiameter), fmt::arg("rho", kDensity), fmt::arg("steps", steps));
  const std::string cmd =
      fmt::format("cd '{}' && OMP_NUM_THREADS=1 liggghts -in in.bench -log none > out.txt 2>&1", dir.string());
  const int rc = std::system(cmd.c_str());
  std::ifstream in(dir / "out.txt");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove_all(dir);
  // "Loop time of T on 1 procs for S steps with N atoms": the last one is the timed run.
  const std::regex loop(R"(Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms)");
  Timing t;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), loop); it != std::sregex_iterator(); ++it)
    if (std::stol((*it)[2]) == steps) t = {std::stol((*it)[3]), std::stod((*it)[1])};
  if (rc != 0 || t.seconds <= 0) {
    note = fmt::format("liggghts failed (exit {}); its output ends: {}", rc,
                       text.substr(text.size() > 400 ? text.size() - 400 : 0));
    return {};
  }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  long steps = 1000;
  CLI::App app{"bench-dem: soft-sphere DEM against LIGGGHTS (see bench/dem.cpp)"};
  coflow::bench::add_steps(app, steps, "timed steps per case");
  coflow::bench::parse_args(app, argc, argv);
  MPI_Init(&argc, &argv);
  log::init("bench", 1);  // rank 1: warnings only
  const double L = kSide * kSpacing;

  // (a) dense lattice: the overlapping spheres are written as a coflow particle
  // file (the configuration checks reject overlapping lattices without bonds).
  const auto tmp = std::filesystem::temp_directory_path() / fmt::format("coflow-bench-dem-lattice-{}.h5", ::getpid());
  {
    const std::size_t n = std::size_t(kSide) * kSide * kSide;
    std::vector<std::int64_t> id(n);
    std::vector<std::int32_t> species(n, 0);
    std::vector<double> x(3 * n), zero(3 * n, 0.0), radius(n, 0.5 * kDiameter);
    for (std::size_t k = 0; k < n; ++k) {
      id[k] = static_cast<std::int64_t>(k);
      const std::size_t ijk[3] = {k % kSide, (k / kSide) % kSide, k / (std::size_t(kSide) * kSide)};
      for (int q = 0; q < 3; ++q) x[3 * k + q] = (double(ijk[q]) + 0.5) * kSpacing;
    }
    output::write_points(MPI_COMM_WORLD, tmp.string(), 0.0, 0, n, id, species,
                         {{"position", 3, x}, {"velocity", 3, zero}, {"angular_velocity", 3, zero},
                          {"radius", 1, radius}});
  }
  const std::string dense = fmt::format(R"(
run: {{name: bench-dem-dense, end_time: 1.0}}
domain: {{lower: [0, 0, 0], upper: [{L:.9g}, {L:.9g}, {L:.9g}], cells: [40, 40, 40], periodic: [true, true, true]}}
particles:
  solver: dem
  time_step: {dt:.9g}
  species: {{grain: {{density: {rho}, diameter: {d:.9g}}}}}
  contact: {{normal_stiffness: 1.0e4, shear_stiffness: 1.0e4, friction: {mu}, local_damping: 0.0}}
  initial:
    - {{file: {{path: {path}}}}}
)",
                                        fmt::arg("L", L), fmt::arg("dt", kStep), fmt::arg("rho", kDensity),
                                        fmt::arg("d", kDiameter), fmt::arg("mu", kFriction),
                                        fmt::arg("path", tmp.string()));
  std::printf("bench-dem: 1 rank, %ld steps per case\n", steps);
  const Timing a = run_coflow(dense, steps);
  std::filesystem::remove(tmp);
  std::printf("(a) dense lattice, coflow dem: %ld particles, %.2f s, %.3e particle-steps/s\n", a.particles,
              a.seconds, a.psps(steps));
  std::string note;
  const Timing b = run_liggghts(steps, note);
  if (b.particles > 0)
    std::printf("(a) dense lattice, LIGGGHTS:   %ld particles, %.2f s, %.3e particle-steps/s\n", b.particles,
                b.seconds, b.psps(steps));
  else
    std::printf("(a) LIGGGHTS: %s\n", note.c_str());

  // (b) pour: 100 000 grains falling in a box.
  const std::string pour = R"(
run: {name: bench-dem-pour, end_time: 1.0, seed: 3}
domain: {lower: [0, 0, 0], upper: [0.06, 0.06, 0.09], cells: [60, 60, 90]}
gravity: [0.0, 0.0, -9.81]
particles:
  solver: dem
  time_step: 1.0e-6
  species: {grain: {density: 2650.0, diameter: {uniform: {min: 0.8e-3, max: 1.2e-3}}}}
  contact: {normal_stiffness: 1.0e4, shear_stiffness: 1.0e4, friction: 0.5, local_damping: 0.3}
  initial:
    - {random: {species: grain, count: 100000, region: {lower: [0, 0, 0], upper: [0.06, 0.06, 0.09]}, velocity_std: 0.5}}
)";
  const Timing p = run_coflow(pour, steps);
  std::printf("(b) pour, coflow dem: %ld particles, %.2f s, %.3e particle-steps/s\n", p.particles, p.seconds,
              p.psps(steps));

  const double ratio = b.particles > 0 ? a.psps(steps) / b.psps(steps) : std::nan("");
  std::printf("RESULT coflow_psps=%.4g liggghts_psps=%.4g ratio=%.3f\n", a.psps(steps),
              b.particles > 0 ? b.psps(steps) : std::nan(""), ratio);
  MPI_Finalize();
  return 0;
}
