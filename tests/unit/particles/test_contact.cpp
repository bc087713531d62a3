#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include "coflow/catalog.hpp"
#include "particles/dem/contact.hpp"
#include "particles/dem/dem_solver.hpp"
#include "particles/dem_reference/dem_reference.hpp"
#include "particles/particles_interface.hpp"
#include "particles/schema.hpp"
#include "tests/unit/worst.hpp"

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

namespace {

// A 2 mm sand grain resting on the floor (domain face z-) at its equilibrium
// overlap delta = m g / K_N, pushed sideways by a constant external force F at its
// centre and held against rolling by the torque -(R - delta) F e_y (the lever of
// the contact force is the distance to the plane), so that friction alone holds it.
struct Block {
  coflow::config::Config cfg;
  coflow::particles::ParticleParams params;
  std::unique_ptr<coflow::particles::DemSolver> dem;
  double m = 0, R = 1e-3, mu = 0.3, fn = 0, arm = 0;

  explicit Block(double alpha) {
    const double m0 = 2650.0 * 4.0 / 3.0 * M_PI * R * R * R;
    const double delta = m0 * 9.81 / 1.0e3;
    const std::string text = fmt::format(R"(
run: {{name: friction, end_time: 1.0}}
domain: {{lower: [0, 0, 0], upper: [0.02, 0.02, 0.02], cells: [10, 10, 10]}}
gravity: [0.0, 0.0, -9.81]
particles:
  solver: dem
  species: {{grain: {{density: 2650.0, diameter: 2.0e-3}}}}
  contact: {{normal_stiffness: 1.0e3, shear_stiffness: 1.0e3, friction: {}, local_damping: {}}}
  initial:
    - {{single: {{species: grain, position: [0.01, 0.01, {:.17g}]}}}}
)",
                                         mu, alpha, R - delta);
    cfg = coflow::config::parse_config_node(YAML::Load(text), "friction.yaml", coflow::catalog());
    coflow::config::Reader r(cfg.resolved["particles"], "friction.yaml", "particles");
    params.visit(r, cfg);
    dem = std::make_unique<coflow::particles::DemSolver>(
        coflow::particles::ParticleSolver::Setup{cfg, params, coflow::coupler::Decomposition({10, 10, 10}, 1), 0,
                                                 MPI_COMM_SELF},
        coflow::particles::DemSolver::Params{});
    m = dem->particles().mass[0];
    fn = m * 9.81;
    arm = R - delta;
  }
  void push(double F) {
    const double force[3] = {F, 0, 0}, torque[3] = {0, -arm * F, 0};
    dem->set_hydrodynamic(force, torque);
  }
  double x() const { return dem->particles().x[0]; }
  double vx() const { return dem->particles().v[0]; }
  // Velocity of the material point at the contact, v + omega x (-arm e_z), along x.
  double slip() const { return dem->particles().v[0] - arm * dem->particles().w[1]; }
  double contact_fx() const { return dem->particles().force[0]; }
};

}  // namespace

TEST_CASE("a grain on a wall sticks below mu F_N and slides above it (solver level)", "[dem]") {
  for (const double fraction : {0.5, 0.95}) {
    // F = fraction mu F_N: friction balances F once the tangential oscillation is damped
    INFO("F / (mu F_N) = " << fraction);
    Block b(0.5);
    const double F = fraction * b.mu * b.fn;
    b.push(F);
    const double x0 = b.x(), dt = b.dem->time_step();
    for (int n = 0; n < 40000; ++n) b.dem->step(dt);
    // At rest: no slip, no rolling, friction equal and opposite to F.
    INFO("contact fx " << b.contact_fx() << " F " << F << " slip " << b.slip());
    CHECK(std::abs(b.contact_fx() + F) < 1e-9 * F);  // force balance
    CHECK(std::abs(b.slip()) < 1e-12);
    CHECK(std::abs(b.vx()) < 1e-12);
    CHECK(std::abs(b.x() - x0) < 2 * F / 1.0e3);  // only the spring's elongation
  }
  for (const double fraction : {1.05, 2.0}) {
    // F = fraction mu F_N: the grain slides with friction mu F_N and acceleration (F - mu F_N) / m
    INFO("F / (mu F_N) = " << fraction);
    Block b(0.0);
    const double F = fraction * b.mu * b.fn;
    b.push(F);
    const double x0 = b.x(), dt = b.dem->time_step();
    for (int n = 0; n < 2000; ++n) b.dem->step(dt);
    const double v0 = b.vx();
    const int steps = 1000;
    double worst = 0;
    for (int n = 0; n < steps; ++n) {
      b.dem->step(dt);
      worst = coflow::test::worst_of(worst, std::abs(std::abs(b.contact_fx()) - b.mu * b.fn) / (b.mu * b.fn));
    }
    INFO("friction error " << worst);
    CHECK(worst < 1e-9);  // Coulomb: |f_t| = mu f_n, and f_n = m g at the equilibrium overlap
    CHECK((b.vx() - v0) / (steps * dt) == Approx((F - b.mu * b.fn) / b.m).epsilon(1e-9));
    CHECK(b.x() - x0 > 20 * F / 1.0e3);  // it slid, far beyond the spring's elongation
  }
}

namespace {

// Three 1 mm grains touching in a row along x (ids 0, 1, 2), cemented with a
// tensile strength of 1e4 Pa x (1 mm)^2 = 0.01 N; `extra` adds bond keys.
template <class Solver>
struct Row {
  coflow::config::Config cfg;
  coflow::particles::ParticleParams params;
  std::unique_ptr<Solver> dem;
  explicit Row(const std::string& extra) {
    const std::string text = fmt::format(R"(
run: {{name: row, end_time: 1.0e-3}}
domain: {{lower: [0, 0, 0], upper: [0.012, 0.01, 0.01], cells: [12, 10, 10]}}
particles:
  solver: dem
  time_step: 1.0e-7
  species: {{grain: {{density: 2650.0, diameter: 1.0e-3}}}}
  contact:
    normal_stiffness: 1.0e4
    shear_stiffness: 1.0e4
    bond: {{compressive_strength: 1.0e8, tensile_strength: 1.0e4, shear_strength: 1.0e8 {}}}
  initial:
    - {{single: {{species: grain, position: [0.0045, 0.005, 0.005]}}}}
    - {{single: {{species: grain, position: [0.0055, 0.005, 0.005]}}}}
    - {{single: {{species: grain, position: [0.0065, 0.005, 0.005]}}}}
)",
                                         extra);
    cfg = coflow::config::parse_config_node(YAML::Load(text), temp_dir() + "/row.yaml", coflow::catalog());
    coflow::config::Reader r(cfg.resolved["particles"], "row.yaml", "particles");
    params.visit(r, cfg);
    dem = std::make_unique<Solver>(coflow::particles::ParticleSolver::Setup{cfg, params,
                                                                            coflow::coupler::Decomposition({12, 10, 10}, 1),
                                                                            0, MPI_COMM_SELF},
                                   typename Solver::Params{});
  }
  static std::string temp_dir() { return std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp"; }
  void pull(double f0, double f2) {
    const double force[9] = {f0, 0, 0, 0, 0, 0, f2, 0, 0}, torque[9] = {};
    dem->set_hydrodynamic(force, torque);
  }
  double gap(int a, int b) const {
    const auto& p = dem->particles();
    return std::abs(p.x[3 * b] - p.x[3 * a]) - p.radius[a] - p.radius[b];
  }
};

}  // namespace

TEST_CASE("bonds from a file cement only the listed pairs", "[dem]") {
  const std::string file = Row<coflow::particles::DemSolver>::temp_dir() + "/coflow-test-bonds.csv";
  std::ofstream(file) << "# bonded pairs\ni,j\n1,0\n";  // either order
  auto check = [](auto& row) {
    row.pull(-0.003, 0.003);  // below the 0.01 N strength even with the dynamic overshoot
    for (int n = 0; n < 3000; ++n) row.dem->step(1e-7);
    CHECK(row.gap(0, 1) < 1e-6);   // held by its bond (stretch < 0.01 N / K_N)
    CHECK(row.gap(1, 2) > 1e-5);   // not listed: free to separate
    CHECK(row.dem->stats().broken_bonds == 0);
  };
  Row<coflow::particles::DemSolver> a(", pairs: coflow-test-bonds.csv");
  Row<coflow::particles::DemReference> b(", pairs: coflow-test-bonds.csv");
  check(a);
  check(b);
  for (std::size_t k = 0; k < a.dem->particles().x.size(); ++k)
    CHECK(a.dem->particles().x[k] == b.dem->particles().x[k]);
  // Without the file, every touching pair is cemented.
  Row<coflow::particles::DemSolver> all("");
  all.pull(-0.003, 0.003);
  for (int n = 0; n < 3000; ++n) all.dem->step(1e-7);
  CHECK(all.gap(1, 2) < 1e-6);
  // A listed pair that does not exist, or lies beyond the gap, is an error naming the line.
  std::ofstream(file) << "i,j\n0,1\n1,7\n";
  CHECK_THROWS_WITH(Row<coflow::particles::DemSolver>(", pairs: coflow-test-bonds.csv"),
                    Catch::Contains("coflow-test-bonds.csv:3") && Catch::Contains("no particle has id 7"));
  std::ofstream(file) << "i,j\n0,2\n";
  CHECK_THROWS_WITH(Row<coflow::particles::DemReference>(", pairs: coflow-test-bonds.csv"),
                    Catch::Contains("coflow-test-bonds.csv:2") && Catch::Contains("more than"));
  std::remove(file.c_str());
}

TEST_CASE("bond failures are logged with their mode and force", "[dem]") {
  // Grain 0 pulled away with 0.02 N: the bond 0-1 fails in tension at
  // sigma_T (R1 + R2)^2 = 0.01 N, within one step's force increment.
  Row<coflow::particles::DemSolver> a("");
  Row<coflow::particles::DemReference> b("");
  for (auto* s : {static_cast<coflow::particles::ParticleSolver*>(a.dem.get()),
                  static_cast<coflow::particles::ParticleSolver*>(b.dem.get())})
    s->record_events(true, true);
  a.pull(-0.02, 0.0);
  b.pull(-0.02, 0.0);
  std::vector<coflow::particles::BondEvent> ea, eb;
  for (int n = 0; n < 5000 && ea.empty(); ++n) {
    a.dem->step(1e-7);
    b.dem->step(1e-7);
    ea = a.dem->take_events().bonds;
    eb = b.dem->take_events().bonds;
  }
  REQUIRE(ea.size() == 1);
  REQUIRE(eb.size() == 1);
  CHECK(ea[0].i == 0);
  CHECK(ea[0].j == 1);
  CHECK(ea[0].mode == coflow::particles::BondFailure::tension);
  // The force one step before was below the strength: the overshoot is at most
  // K_N |relative velocity| dt.
  const auto& p = a.dem->particles();
  const double increment = 1.0e4 * std::abs(p.v[0] - p.v[3]) * 1e-7;
  CHECK(-ea[0].normal_force >= 0.01);
  CHECK(-ea[0].normal_force <= 0.01 + increment);
  CHECK(ea[0].time == eb[0].time);
  CHECK(ea[0].normal_force == eb[0].normal_force);
}

// A step split into more parts than a run counts stops with a message (before
// 2026-12-07 the count was cast to a long unchecked: 1e300 parts is undefined,
// and a large positive count a run that never ends).
TEST_CASE("split_for: equal parts, and none beyond counting", "[contact]") {
  CHECK(split_for(1e-3, 1e-4) == 10);
  CHECK(split_for(1e-3, 1e-3 * (1 + 1e-12)) == 1);
  CHECK(split_for(1e-3, 2e-3) == 1);
  CHECK(split_for(1.0, 1e-15) == 1000000000000000L);
  CHECK_THROWS_WITH(split_for(1.0, 1e-300), Catch::Contains("more than a run can count") &&
                                                Catch::Contains("too light for the contact stiffness"));
  CHECK_THROWS_WITH(split_for(1.0, 0.0, "why"), Catch::Contains("sub-steps") && Catch::Contains(": why"));
  CHECK_THROWS(split_for(1.0, std::nan("")));
}
