#include <catch2/catch.hpp>

#include <cmath>

#include "coflow/catalog.hpp"
#include "particles/dem/contact.hpp"
#include "particles/dem/dem_solver.hpp"
#include "particles/schema.hpp"

using namespace coflow::particles::dem;

namespace {
ContactLaw law() { return ContactLaw{1e4, 5e3, 0.5, 4e6, 1e6, 2e6}; }
const V3 ex(1, 0, 0);
}  // namespace

TEST_CASE("normal force is K_N times the overlap and repulsive", "[dem]") {
  ContactState s;
  const auto c = contact_force(ex, 1e-5, 0.5e-3, 0.5e-3, V3::Zero(), 1e-3, s, law(), 1e-6);
  CHECK(c.active);
  CHECK(c.force.x() == Approx(1e4 * 1e-5).epsilon(1e-15));
  CHECK(c.torque1.norm() == 0.0);
}

TEST_CASE("an unbonded contact carries no tension", "[dem]") {
  ContactState s;
  const auto c = contact_force(ex, -1e-6, 0.5e-3, 0.5e-3, V3::Zero(), 1e-3, s, law(), 1e-6);
  CHECK_FALSE(c.active);
  CHECK(c.force.norm() == 0.0);
}

TEST_CASE("shear force sticks below mu F_N and slides at mu F_N", "[dem]") {
  // Constant overlap (F_N = 0.1 N), steady sliding velocity: the shear force
  // grows by k_S v dt per step until it reaches mu F_N = 0.05 N, then stays there.
  ContactState s;
  const double dt = 1e-6, v = 0.01;
  const V3 vrel(0, v, 0);
  double last = 0.0;
  int steps_to_limit = 0;
  for (int n = 1; n <= 2000; ++n) {
    const auto c = contact_force(ex, 1e-5, 0.5e-3, 0.5e-3, vrel, 1e-3, s, law(), dt);
    const double fs = std::abs(c.force.y());
    if (fs < 0.05 - 1e-12) {
      CHECK(fs == Approx(5e3 * v * dt * n).epsilon(1e-9));  // elastic: sticks
      steps_to_limit = n;
    } else {
      CHECK(fs == Approx(0.05).epsilon(1e-9));  // Coulomb limit: slides
    }
    CHECK(c.force.y() < 0);  // opposes the sliding velocity
    last = fs;
  }
  CHECK(steps_to_limit == 999);  // 0.05 N / (k_S v dt) = 1000 steps
  CHECK(last == Approx(0.05).epsilon(1e-12));
}

TEST_CASE("the stored shear force turns with the contact plane", "[dem]") {
  ContactState s;
  s.shear = V3(0, 0.02, 0);
  const V3 n = V3(1, 1, 0).normalized();
  contact_force(n, 1e-5, 0.5e-3, 0.5e-3, V3::Zero(), 1e-3, s, law(), 1e-6);
  CHECK(std::abs(s.shear.dot(n)) < 1e-15);
  CHECK(s.shear.norm() == Approx(0.02).epsilon(1e-12));
}

TEST_CASE("a bond breaks in tension at sigma_T (R1 + R2)^2 within one step", "[dem]") {
  // Pull a bonded pair apart by a fixed increment per step: it breaks at the
  // first step whose tension exceeds F = sigma_T (R1 + R2)^2 = 1 N.
  ContactState s;
  s.bonded = true;
  const double r_sum = 1e-3, strength = 1e6 * r_sum * r_sum, dx = 2e-7;  // 2e-3 N per step
  double tension_before_break = 0.0;
  for (int n = 1; n < 1000; ++n) {
    const double overlap = -n * dx;
    const auto c = contact_force(ex, overlap, 0.5e-3, 0.5e-3, V3::Zero(), r_sum, s, law(), 1e-6);
    if (c.failure == Failure::tension) {
      CHECK_FALSE(c.active);  // broken and apart: no force
      CHECK(1e4 * n * dx > strength);
      CHECK(tension_before_break <= strength);
      CHECK(strength - tension_before_break <= 1e4 * dx + 1e-12);  // within one step's increment
      return;
    }
    CHECK(c.force.x() == Approx(-1e4 * n * dx));  // bonded: carries tension
    tension_before_break = 1e4 * n * dx;
  }
  FAIL("the bond never broke");
}

TEST_CASE("compressive failure is reported once the bond's strength is passed", "[dem]") {
  ContactState s;
  s.bonded = true;
  const double r_sum = 1e-3, strength = 4e6 * r_sum * r_sum;  // 4 N
  const auto below = contact_force(ex, 0.99 * strength / 1e4, 0.5e-3, 0.5e-3, V3::Zero(), r_sum, s, law(), 1e-6);
  CHECK(below.failure == Failure::none);
  CHECK(s.bonded);
  const auto above = contact_force(ex, 1.01 * strength / 1e4, 0.5e-3, 0.5e-3, V3::Zero(), r_sum, s, law(), 1e-6);
  CHECK(above.failure == Failure::compression);
  CHECK_FALSE(s.bonded);
  CHECK(above.active);  // still in contact, now frictional
}

TEST_CASE("compressive bond failure crushes both grains by crush_fraction", "[dem]") {
  // Two bonded grains driven together: when the bond fails in compression both
  // radii shrink by exactly crush_fraction and the masses by its cube. The
  // strength, 1e4 Pa x (1 mm)^2 = 0.01 N, is reached at an overlap of 1 um.
  const char* text = R"(
run: {name: crush, end_time: 1.0e-3}
domain: {lower: [0, 0, 0], upper: [0.01, 0.01, 0.01], cells: [10, 10, 10]}
particles:
  solver: dem
  time_step: 1.0e-7
  species: {grain: {density: 2650.0, diameter: 1.0e-3}}
  contact:
    normal_stiffness: 1.0e4
    shear_stiffness: 1.0e4
    friction: 0.5
    bond: {compressive_strength: 1.0e4, tensile_strength: 1.0e6, shear_strength: 1.0e6, crush_fraction: 0.01, gap: 1.0e-6}
  initial:
    - {single: {species: grain, position: [0.0045, 0.005, 0.005], velocity: [0.5, 0, 0]}}
    - {single: {species: grain, position: [0.0055, 0.005, 0.005], velocity: [-0.5, 0, 0]}}
)";
  const auto cfg = coflow::config::parse_config_node(YAML::Load(text), "crush.yaml", coflow::catalog());
  coflow::particles::ParticleParams params;
  coflow::config::Reader r(cfg.resolved["particles"], "crush.yaml", "particles");
  params.visit(r, cfg);
  const coflow::coupler::Decomposition dec({10, 10, 10}, 1);
  coflow::particles::DemSolver dem({cfg, params, dec, 0, MPI_COMM_SELF}, {});
  const double r0 = dem.particles().radius[0], m0 = dem.particles().mass[0];
  long broken = 0;
  for (int n = 0; n < 2000 && broken == 0; ++n) {
    dem.step(1e-7);
    broken = dem.stats().broken_bonds;
  }
  REQUIRE(broken == 1);
  for (int i = 0; i < 2; ++i) {
    CHECK(dem.particles().radius[i] == Approx(0.99 * r0).epsilon(1e-15));
    CHECK(dem.particles().mass[i] == Approx(std::pow(0.99, 3) * m0).epsilon(1e-14));
  }
}
