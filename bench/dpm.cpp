// Benchmark: dpm point particles, 1 rank.
//
//   build/bin/bench-dpm [steps]
//
// (a) the granular gas of seed 003 §5.2: 100 000 elastic spheres of 342.1 um at
//     solid fraction 0.001 in a periodic cube of 0.128 m, velocities N(0, 0.236
//     m/s), step 5e-5 s: particle-steps per second with collisions on and off;
// (b) collision detection for N = 5 000 (same fraction): cell lists against
//     every pair, in the same run (their ratio);
// (c) the granular jet on a plate (configs/validation/dpm_jet_plate.yaml,
//     seed 003 §5.3, the 104 972-triangle plate written by
//     scripts/make_plate_stl.py): run to 0.01 s, then the mesh-collision search
//     of one step for the particles then in flight, with FCL's candidates and
//     with every triangle (on a subset of the particles, scaled), and the
//     events both find (they must be the same).
// Last line: RESULT psps_collisions=... psps_free=... detection_speedup=... mesh_speedup=...
#include <fmt/format.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include "bench_args.hpp"
#include "coflow/catalog.hpp"
#include "coflow/log.hpp"
#include "coflow/trace.hpp"
#include "particles/dpm/dpm_solver.hpp"
#include "particles/dpm/setup.hpp"
#include "particles/particles_interface.hpp"
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

struct Jet {
  config::Config cfg;
  particles::ParticleParams params;
};

// Mesh-collision search of one step for the particles of `s`, FCL candidates
// vs every triangle; returns the speedup and prints the figures.
double mesh_speedup() {
  const std::string src = COFLOW_SOURCE_DIR;
  const std::string plate = "bench-dpm-plate.stl";
  if (std::system(("/usr/bin/python3 " + src + "/scripts/make_plate_stl.py " + plate + " > /dev/null").c_str()) != 0) {
    std::printf("(c) jet on a plate: could not write the plate (python3)\n");
    return std::nan("");
  }
  Jet j;
  YAML::Node root = YAML::LoadFile(src + "/configs/validation/dpm_jet_plate.yaml");
  YAML::Node wall;
  wall["mesh"] = std::filesystem::absolute(plate).string();
  wall["restitution"] = 0.3;
  wall["friction"] = 0.1;
  root["particles"]["walls"] = std::vector<YAML::Node>{wall};
  j.cfg = config::parse_config_node(root, src + "/configs/validation/dpm_jet_plate.yaml", catalog());
  config::Reader r(j.cfg.resolved["particles"], "bench", "particles");
  j.params.point_particles = true;
  j.params.visit(r, j.cfg);
  const coupler::Decomposition dec({20, 20, 20}, 1, {1, 1, 1}, {false, false, false});
  particles::DpmSolver solver(particles::ParticleSolver::Setup{j.cfg, j.params, dec, 0, MPI_COMM_WORLD},
                              particles::DpmSolver::Params{});
  const double h = 5e-5;
  for (int k = 0; k < 200; ++k) solver.step(h);
  const auto& p = solver.particles();
  particles::dpm::DpmSetup set = particles::dpm::make_setup(j.params, j.cfg);
  const std::size_t n = p.size(), stride = std::max<std::size_t>(1, n / 400);
  auto search = [&](bool all, std::size_t every, std::vector<particles::dpm::Event>& ev) {
    set.mesh_all_triangles = all;
    std::vector<int> scratch;
    ev.clear();
    const double t0 = coupler::now();
    for (std::size_t i = 0; i < n; i += every) {
      const particles::dpm::V3 x(&p.x[3 * i]), v(&p.v[3 * i]);
      particles::dpm::mesh_events(x, v, 2.0 * p.radius[i], p.id[i], i, h, set, scratch, ev);
    }
    return coupler::now() - t0;
  };
  std::vector<particles::dpm::Event> fcl_all, fcl_sub, brute_sub;
  const double t_fcl = search(false, 1, fcl_all);
  const double t_fcl_sub = search(false, stride, fcl_sub);
  const double t_brute_sub = search(true, stride, brute_sub);
  bool same = fcl_sub.size() == brute_sub.size();
  for (std::size_t k = 0; same && k < fcl_sub.size(); ++k)
    same = fcl_sub[k].t == brute_sub[k].t && fcl_sub[k].b == brute_sub[k].b;
  const double speedup = t_brute_sub / t_fcl_sub;
  std::printf("(c) jet on a plate (%zu triangles) at 0.01 s, %zu particles in flight:\n", set.meshes[0]->size(), n);
  std::printf("    mesh search, one step, FCL candidates: %.3e s (%zu wall events)\n", t_fcl, fcl_all.size());
  std::printf("    on every %zu-th particle: FCL %.3e s, every triangle %.3e s: %.0fx (cost reduced by %.3f %%), "
              "events %s (%zu)\n",
              stride, t_fcl_sub, t_brute_sub, speedup, 100.0 * (1.0 - 1.0 / speedup), same ? "identical" : "DIFFER",
              fcl_sub.size());
  std::filesystem::remove(plate);
  return speedup;
}

}  // namespace

int main(int argc, char** argv) {
  int steps = 50;
  CLI::App app{"bench-dpm: point-particle throughput (see bench/dpm.cpp)"};
  coflow::bench::add_steps(
      app, steps, "timed steps of (a) and of (b)'s cell lists ((b)'s all pairs: a fifth; (c) a fixed 200)");
  coflow::bench::parse_args(app, argc, argv);
  MPI_Init(&argc, &argv);
  log::init("bench", 1);  // warnings only
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
  const double mesh = mesh_speedup();
  std::printf("RESULT psps_collisions=%.4g psps_free=%.4g detection_speedup=%.1f mesh_speedup=%.1f\n", with, without,
              fast / slow, mesh);
  MPI_Finalize();
  return 0;
}
