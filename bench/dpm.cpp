// Benchmark: dpm point particles, 1 rank.
//
//   build/bin/bench-dpm [steps]
//
// (a) the granular gas of seed 003 §5.2: 100 000 elastic spheres of 342.1 um at
//     solid fraction 0.001 in a periodic cube of 0.128 m, velocities N(0, 0.236
//     m/s), step 5e-5 s: particle-steps per second with collisions on and off;
// (b) collision detection for N = 5 000 (same fraction): cell lists against
//     every pair, in the same run (their ratio);
// (c) the jet-on-plate mesh collisions: not implemented yet (triangle-mesh
//     walls are not in dpm), printed as n/a.
// Last line: RESULT psps_collisions=... psps_free=... detection_speedup=... mesh_speedup=...
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include <fmt/format.h>

#include "coflow/catalog.hpp"
#include "coflow/log.hpp"
#include "coflow/trace.hpp"
#include "particles/dpm/dpm_solver.hpp"
#include "particles/schema.hpp"

using namespace coflow;

namespace {

struct Gas {
  config::Config cfg;
  particles::ParticleParams params;
  std::unique_ptr<particles::DpmSolver> solver;
};

std::unique_ptr<Gas> make_gas(long n, bool collisions) {
  const double D = 342.1e-6, alpha = 0.001;
  const double L = std::cbrt(n * std::numbers::pi * D * D * D / 6.0 / alpha);
  const std::string text = fmt::format(R"(
run: {{name: bench-dpm, end_time: 1.0}}
domain: {{lower: [0, 0, 0], upper: [{0}, {0}, {0}], cells: [8, 8, 8], periodic: [true, true, true]}}
gravity: [0, 0, 0]
particles:
  solver: dpm
  time_step: 5.0e-5
  species:
    glass: {{density: 1000.0, diameter: {1}}}
  collision: {{restitution: 1.0, friction: 0.0, enabled: {2}}}
  initial:
    - {{random: {{species: glass, count: {3}, region: {{lower: [0, 0, 0], upper: [{0}, {0}, {0}]}}, velocity_std: 0.236}}}}
)",
                                       L, D, collisions ? "true" : "false", n);
  auto g = std::make_unique<Gas>();
  g->cfg = config::parse_config_node(YAML::Load(text), "bench", catalog());
  config::Reader r(g->cfg.resolved["particles"], "bench", "particles");
  g->params.point_particles = true;
  g->params.visit(r, g->cfg);
  const coupler::Decomposition dec({8, 8, 8}, 1, {1, 1, 1}, {true, true, true});
  g->solver = std::make_unique<particles::DpmSolver>(
      particles::ParticleSolver::Setup{g->cfg, g->params, dec, 0, MPI_COMM_WORLD}, particles::DpmSolver::Params{});
  return g;
}

double psps(particles::DpmSolver& s, int steps) {
  s.step(5e-5);  // warm-up
  const double t0 = coupler::now();
  for (int k = 0; k < steps; ++k) s.step(5e-5);
  return static_cast<double>(s.particles().size()) * steps / (coupler::now() - t0);
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  log::init("bench", 1);  // warnings only
  const int steps = argc > 1 ? std::atoi(argv[1]) : 50;
  auto on = make_gas(100000, true);
  const double with = psps(*on->solver, steps);
  const long collisions = on->solver->stats().collisions;
  auto off = make_gas(100000, false);
  const double without = psps(*off->solver, steps);
  std::printf("(a) granular gas, 100000 particles, alpha 0.001, %d steps of 5e-5 s, 1 rank:\n", steps);
  std::printf("    collisions on : %.3e particle-steps/s (%ld collisions)\n", with, collisions);
  std::printf("    collisions off: %.3e particle-steps/s\n", without);
  auto cells = make_gas(5000, true);
  auto pairs = make_gas(5000, true);
  pairs->solver->use_all_pairs(true);
  const double fast = psps(*cells->solver, steps), slow = psps(*pairs->solver, std::max(5, steps / 5));
  std::printf("(b) detection, 5000 particles: cell lists %.3e, all pairs %.3e particle-steps/s: %.1fx\n", fast, slow,
              fast / slow);
  std::printf("(c) jet on a plate, mesh collisions: n/a (triangle-mesh walls are not implemented in dpm yet)\n");
  std::printf("RESULT psps_collisions=%.4g psps_free=%.4g detection_speedup=%.1f mesh_speedup=nan\n", with, without,
              fast / slow);
  MPI_Finalize();
  return 0;
}
