// Point particles at the faces of the box. Inlets place no particle where it
// would overlap another, of any species. Particles leaving through an outlet
// keep the fluid's momentum: the impulse of the fluid forces on a particle over the window until it left
// is handed back (take_departed) at its last position inside, so that the
// fluid gets -impulse there (two-way coupling). Checked against the momentum
// theorem (the impulse equals m (v - v0) with drag alone) on a twin run
// whose outlet is farther away, for dpm and dpm-reference.
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "coflow/catalog.hpp"
#include "particles/dpm/dpm_solver.hpp"
#include "particles/dpm_reference/dpm_reference.hpp"
#include "particles/particles_interface.hpp"
#include "particles/schema.hpp"

namespace {

using coflow::particles::DepartedImpulse;
using coflow::particles::ParticleSolver;

struct Run {
  coflow::config::Config cfg;
  coflow::particles::ParticleParams params;
  std::unique_ptr<ParticleSolver> solver;
  // `particles`: the particles section after its solver and time step.
  Run(const std::string& variant, double upper, const std::string& particles) {
    const std::string text =
        "run: {name: faces, end_time: 1.0}\n"
        "domain: {lower: [0, 0, 0], upper: [" +
        std::to_string(upper) + ", 0.1, 0.1], cells: [" +
        std::to_string(static_cast<int>(std::lround(upper * 100))) +
        ", 10, 10]}\n"
        "gravity: [0, 0, 0]\n"
        "fluid: {solver: analytic, density: 1000.0, viscosity: 1.0e-6}\n"
        "particles:\n  solver: " +
        variant + "\n  time_step: 1.0e-4\n" + particles;
    cfg = coflow::config::parse_config_node(YAML::Load(text), "faces.yaml", coflow::catalog());
    coflow::config::Reader r(cfg.resolved["particles"], "faces.yaml", "particles");
    params.visit(r, cfg);
    const coflow::coupler::Decomposition dec({std::lround(upper * 100), 10, 10}, 1);
    const ParticleSolver::Setup setup{cfg, params, dec, 0, MPI_COMM_SELF};
    if (variant == "dpm")
      solver = std::make_unique<coflow::particles::DpmSolver>(setup, coflow::particles::DpmSolver::Params{});
    else
      solver =
          std::make_unique<coflow::particles::DpmReference>(setup, coflow::particles::DpmReference::Params{});
  }
};

// A 1 mm bead shot at 1 m/s along x into still water from x = 90 mm; the
// box ends at x = 0.1 m (an outlet), its twin's at 0.2 m.
void check_outlet(const std::string& variant) {
  const std::string bead =
      "  species: {bead: {density: 2000.0, diameter: 1.0e-3}}\n"
      "  forces: [drag]\n  boundaries: {x+: outlet}\n"
      "  initial:\n    - {single: {species: bead, position: [0.09, 0.05, 0.05], "
      "velocity: [1.0, 0, 0]}}\n";
  Run near(variant, 0.1, bead), far(variant, 0.2, bead);
  const double m = 2000.0 * M_PI / 6.0 * 1e-9, v0 = 1.0;
  std::vector<double> impulse;
  std::vector<DepartedImpulse> departed;
  double given = 0.0, far_given = 0.0;  // x impulse so far
  // Windows of ten steps: the bead leaves in the middle of one.
  for (int window = 0; window < 100 && departed.empty(); ++window) {
    near.solver->advance(1e-3, 10);
    near.solver->take_impulse(impulse);
    for (std::size_t i = 0; i < impulse.size(); i += 3) given += impulse[i];
    near.solver->take_departed(departed);
  }
  // The twin, a step at a time, up to the step that crosses x = 0.1.
  std::array<double, 3> far_before{};
  for (int step = 0; step < 1000 && far.solver->particles().x.at(0) < 0.1; ++step) {
    for (int a = 0; a < 3; ++a) far_before[a] = far.solver->particles().x[a];
    far.solver->advance(1e-4, 1);
    far.solver->take_impulse(impulse);
    far_given += impulse.at(0);
  }
  REQUIRE(departed.size() == 1);
  REQUIRE(near.solver->particles().size() == 0);
  const DepartedImpulse& d = departed[0];
  given += d.impulse[0];
  INFO(variant << ": impulse " << given << " N s, the far run's " << far_given);
  // Where it was at the start of the step it left in: inside, on its path.
  CHECK(d.x[0] < 0.1);
  CHECK(d.x == far_before);
  // The whole impulse comes back: that of the twin, which drag alone gave
  // (summed by windows here, by steps there: the same to round-off; 4.4e-16
  // relative measured with both variants, 2026-12-03).
  CHECK(std::abs(given - far_given) <= 5e-15 * std::abs(far_given));
  const double v = far.solver->particles().v.at(0);
  CHECK(v < 0.999 * v0);  // drag did act
  // The momentum theorem: the impulses are the steps' m dv, which telescope
  // (0 measured with both variants; the bound is about ten ulp).
  CHECK(std::abs(given - m * (v - v0)) <= 2e-15 * m * (v0 - v));
  CHECK(d.impulse[1] == 0.0);
  CHECK(d.impulse[2] == 0.0);
  // Nothing left over for the next window.
  near.solver->take_departed(departed);
  CHECK(departed.empty());
}

// A 30 mm boulder at rest over a 20 mm inlet of 0.1 mm dust at 20 m/s: its
// centre is 16.3 mm from the inlet's, farther than the inlet's own species
// alone would reach (10 mm + 2 mm travel + 2 x 0.1 mm), but its lower part
// covers much of where the dust ends its first step. No dust may overlap it.
std::size_t overlaps_after_injection(const std::string& variant) {
  const std::string text =
      "  species:\n"
      "    dust: {density: 1000.0, diameter: 1.0e-4}\n"
      "    boulder: {density: 1000.0, diameter: 0.03}\n"
      "  forces: [drag]\n"
      "  injection:\n"
      "    - {species: dust, mass_flow: 5.0e-4, speed: 20.0, disk: {center: [0.05, 0.05, 0.0], "
      "normal: [0, 0, 1], diameter: 0.02}}\n"
      "  initial:\n    - {single: {species: boulder, position: [0.055, 0.05, 0.0155]}}\n";
  Run run(variant, 0.1, text);
  run.solver->advance(1e-4, 1);
  const auto& p = run.solver->particles();
  REQUIRE(p.size() > 50);  // about 96 dust particles owed in the step
  std::size_t boulder = p.size(), overlapping = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.radius[i] > 0.01) boulder = i;
  REQUIRE(boulder < p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (i == boulder) continue;
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a)
      d2 += (p.x[3 * i + a] - p.x[3 * boulder + a]) * (p.x[3 * i + a] - p.x[3 * boulder + a]);
    if (std::sqrt(d2) < p.radius[i] + p.radius[boulder]) ++overlapping;
  }
  return overlapping;
}

}  // namespace

TEST_CASE("inlets place no particle overlapping one of a wider species", "[dpm]") {
  CHECK(overlaps_after_injection("dpm") == 0);
  CHECK(overlaps_after_injection("dpm-reference") == 0);
}

TEST_CASE("a particle that leaves through an outlet hands its window's fluid impulse back", "[dpm]") {
  check_outlet("dpm");
  check_outlet("dpm-reference");
}
