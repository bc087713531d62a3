// Point particles (seed 003): force coefficients against hand-computed values of
// the published correlations, the hard-sphere collision laws against the
// conservation laws they must obey, the contact time of eq. 4.28, and the RK4
// integration against the analytic Stokes response.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "coflow/catalog.hpp"
#include "particles/dpm/collision.hpp"
#include "particles/dpm/forces.hpp"
#include "particles/dpm/injection.hpp"
#include "particles/dpm/setup.hpp"
#include "particles/dpm_reference/dpm_reference.hpp"
#include "particles/particles_interface.hpp"
#include "particles/schema.hpp"

using namespace coflow::particles::dpm;
using Catch::Matchers::WithinRel;

TEST_CASE("Schiller-Naumann drag coefficient, eq. 3.31", "[dpm]") {
  CHECK_THAT(drag_coefficient(1.0), WithinRel(27.6, 1e-14));                  // 24 (1 + 0.15)
  CHECK_THAT(drag_coefficient(100.0), WithinRel(1.0917310910948732, 1e-13));  // 0.24 (1 + 0.15 100^0.687)
  CHECK_THAT(drag_coefficient(2000.0), WithinRel(0.44, 1e-14));               // Newton regime
  // Stokes limit: the force 3 pi mu D (u - v) with f -> 1.
  FluidSample f;
  f.rho = 1000.0;
  f.mu = 1e-3;
  const ForceSet drag_only{false, true, false, false, false};
  const FluidLoad L = fluid_load(f, 1e-6, V3(1e-6, 0, 0), V3::Zero(), drag_only);
  CHECK_THAT(L.drag[0], WithinRel(-3.0 * std::numbers::pi * 1e-3 * 1e-6 * 1e-6, 1e-4));  // f - 1 = 1.1e-5 at Re 1e-6
}

TEST_CASE("Saffman-Mei, Oesterle-Dinh and Dennis coefficients, eqs 3.32-3.34", "[dpm]") {
  // Re_p = 1, Re_s = 0.5: beta = 0.25, 4.1126 / sqrt(0.5) [(1 - 0.3314 x 0.5) e^-0.1 + 0.3314 x 0.5]
  CHECK_THAT(saffman_coefficient(1.0, 0.5), WithinRel(5.354330847615836, 1e-13));
  // Re_p = 100 > 40: 4.1126 / sqrt(20) x 0.0524 sqrt(beta Re_p), beta Re_p = 10
  CHECK_THAT(saffman_coefficient(100.0, 20.0), WithinRel(0.1523816810513285, 1e-13));
  // gamma = Re_r / (2 Re_p) = 0.1: 0.45 + (0.2 - 0.45) exp(-0.075 x 0.1^0.4 x 50^0.7)
  CHECK_THAT(magnus_coefficient(50.0, 10.0), WithinRel(0.2924438720279928, 1e-13));
  CHECK_THAT(rotation_coefficient(10.0), WithinRel(64.0 * std::numbers::pi / 10.0, 1e-14));
  CHECK_THAT(rotation_coefficient(100.0), WithinRel(12.9 / 10.0 + 1.284, 1e-14));
}

TEST_CASE("lift and torque limits: Rubinow-Keller and Stokes", "[dpm]") {
  FluidSample f;
  f.rho = 1000.0;
  f.mu = 1e-3;
  const double D = 1e-4;
  // A particle spinning in still fluid: T = -pi mu D^3 w (eq. 2.32) at small Re_r.
  const ForceSet torque_only{false, false, false, false, true};
  const FluidLoad T = fluid_load(f, D, V3::Zero(), V3(0, 0, 1.0), torque_only);
  CHECK_THAT(T.torque[2], WithinRel(-std::numbers::pi * 1e-3 * D * D * D * 1.0, 1e-12));
  // Magnus at Re_p -> 0 tends to Rubinow-Keller, pi/8 rho D^3 (Omega x (u - v)).
  const ForceSet magnus_only{false, false, false, true, false};
  const V3 v(1e-5, 0, 0), w(0, 0, 2.0);
  const FluidLoad M = fluid_load(f, D, v, w, magnus_only);
  const V3 rk = std::numbers::pi / 8.0 * f.rho * D * D * D * (-w).cross(-v);
  CHECK_THAT(M.magnus[1], WithinRel(rk[1], 2e-3));
  CHECK(std::abs(M.magnus[0]) < 1e-30);
  // Saffman lift is perpendicular to the slip and to the vorticity.
  f.vorticity = V3(0, 0, 50.0);
  const ForceSet saffman_only{false, false, true, false, false};
  const FluidLoad S = fluid_load(f, D, V3(0.01, 0, 0), V3::Zero(), saffman_only);
  CHECK(std::abs(S.saffman.dot(V3(1, 0, 0))) < 1e-20);
  CHECK(std::abs(S.saffman.dot(f.vorticity)) < 1e-20);
  CHECK(S.saffman[1] > 0.0);  // (u - v) x omega = (-0.01 x) x (50 z) = +0.5 y
}

// A particle at rest in a 15 m/s stream, Re_p = 500: the drag relaxes the
// slip at d(f Re)/dRe / tau_p = 19 / tau_p. Eq. 4.15's 0.2 tau_p alone gave h
// lambda = 3.8, beyond RK4's stability limit of 2.785 for the linearised drag
// (found by review, 2026-12-05); the step now keeps h lambda <= 1.
TEST_CASE("the automatic step keeps RK4 stable at large Re_p", "[dpm]") {
  DpmSetup s;
  s.cell = 1.0;
  FluidSample f;
  f.u = V3(15.0, 0, 0);
  f.rho = 1.2;
  f.mu = 1.8e-5;
  const double D = 5e-4, rho_p = 2500.0, tau = response_time(rho_p, D, f.mu);
  const double h = lagrangian_step(s, D, rho_p, V3::Zero(), f);
  const double rate = drag_rate(500.0);
  CHECK_THAT(rate, WithinRel(1.0 + 0.25305 * std::pow(500.0, 0.687), 1e-12));
  CHECK_THAT(h * rate / tau, WithinRel(1.0, 1e-12));
  const double m = rho_p * std::numbers::pi * D * D * D / 6.0, I = m * D * D / 10.0;
  const Motion after = rk4({V3::Zero(), V3::Zero(), V3::Zero()}, D, m, I, rho_p, f, s, h);
  CHECK(after.v[0] > 0.0);
  CHECK(after.v[0] < 15.0);
  // Newton's regime (Re_p 2000): C_d = 0.44, d(f Re)/dRe = 0.88 Re / 24.
  CHECK_THAT(drag_rate(2000.0), WithinRel(0.88 * 2000.0 / 24.0, 1e-14));
  // At small Re_p eq. 4.15's response time is what binds, as before.
  f.u = V3(0.01, 0, 0);  // Re_p 0.33
  CHECK(lagrangian_step(s, D, rho_p, V3::Zero(), f) == 0.2 * tau);
}

TEST_CASE("contact time along straight trajectories, eq. 4.28", "[dpm]") {
  // Head-on at 2 m/s closing speed, gap 1 mm: touch after 0.5 ms.
  CHECK_THAT(contact_time(V3(3e-3, 0, 0), V3(-2.0, 0, 0), 2e-3, 1e-3), WithinRel(5e-4, 1e-12));
  CHECK(std::isinf(contact_time(V3(3e-3, 0, 0), V3(-2.0, 0, 0), 2e-3, 4e-4)));  // later than the step
  CHECK(std::isinf(contact_time(V3(3e-3, 0, 0), V3(2.0, 0, 0), 2e-3, 1.0)));    // separating
  CHECK(std::isinf(contact_time(V3(3e-3, 0, 0), V3(-1.0, 1.0, 0), 2e-3, 1.0)));  // they miss
  // Grazing: impact parameter just inside the reach.
  const double t = contact_time(V3(3e-3, 1.9e-3, 0), V3(-1.0, 0, 0), 2e-3, 1.0);
  CHECK_THAT(t, WithinRel(3e-3 - std::sqrt(4e-6 - 1.9e-3 * 1.9e-3), 1e-9));
}

TEST_CASE("swept sphere against a triangle: face, edge, vertex, miss, receding, touching", "[dpm]") {
  // Triangle in the plane z = 0 with corners (0,0,0), (1,0,0), (0,1,0); R = 0.1.
  const V3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const double R = 0.1, inf = std::numeric_limits<double>::infinity();
  V3 p;
  // Face: centre falls from z = 1 at speed 2 onto (0.2, 0.2): touches at z = R, t = 0.45.
  CHECK(sweep_triangle(V3(0.2, 0.2, 1.0), V3(0, 0, -2), R, 1.0, a, b, c, p) == Approx(0.45).epsilon(1e-14));
  CHECK((p - V3(0.2, 0.2, 0.0)).norm() < 1e-14);
  // From below, the same.
  CHECK(sweep_triangle(V3(0.2, 0.2, -1.0), V3(0, 0, 2), R, 1.0, a, b, c, p) == Approx(0.45).epsilon(1e-14));
  // Edge y = 0: centre at y = -0.06 falls past the face; touches the edge where
  // sqrt(0.06^2 + z^2) = R, z = 0.08: t = (1 - 0.08) / 2.
  CHECK(sweep_triangle(V3(0.5, -0.06, 1.0), V3(0, 0, -2), R, 1.0, a, b, c, p) == Approx(0.46).epsilon(1e-13));
  CHECK((p - V3(0.5, 0.0, 0.0)).norm() < 1e-13);
  // Vertex (1,0,0): moving along x towards it from x = 2: touches at x = 1 + R.
  CHECK(sweep_triangle(V3(2.0, 0.0, 0.0), V3(-1, 0, 0), R, 2.0, a, b, c, p) == Approx(0.9).epsilon(1e-14));
  CHECK((p - b).norm() < 1e-14);
  // Too short a step, passing by, receding: no contact.
  CHECK(sweep_triangle(V3(0.2, 0.2, 1.0), V3(0, 0, -2), R, 0.4, a, b, c, p) == inf);
  CHECK(sweep_triangle(V3(0.8, 0.8, 1.0), V3(0, 0, -2), R, 1.0, a, b, c, p) == inf);  // beyond the hypotenuse
  CHECK(sweep_triangle(V3(0.2, 0.2, 0.5), V3(0, 0, 1), R, 1.0, a, b, c, p) == inf);
  // Within R of the line of edge ab but beyond b, drifting slowly: no contact
  // within the step (the edge's quadratic has a root at t = -50, over the edge).
  CHECK(sweep_triangle(V3(1.2, 0.05, 0.0), V3(0.005, -0.001, 0), R, 1.0, a, b, c, p) == inf);
  // The same start moving towards b: it reaches b's vertex, where
  // (0.2 - t)^2 + 0.05^2 = R^2, t = 0.2 - sqrt(0.0075).
  CHECK(sweep_triangle(V3(1.2, 0.05, 0.0), V3(-1, 0, 0), R, 1.0, a, b, c, p) ==
        Approx(0.2 - std::sqrt(0.0075)).epsilon(1e-13));
  CHECK((p - b).norm() < 1e-14);
  // Already touching and approaching: t = 0; touching and leaving: none.
  CHECK(sweep_triangle(V3(0.2, 0.2, 0.05), V3(0, 0, -1), R, 1.0, a, b, c, p) == 0.0);
  CHECK(sweep_triangle(V3(0.2, 0.2, 0.05), V3(0, 0, 1), R, 1.0, a, b, c, p) == inf);
}

TEST_CASE("hard-sphere pair collisions conserve momentum; e = 1, mu = 0 conserves energy", "[dpm]") {
  const double mp = 2e-6, mq = 5e-6, Dp = 1e-3, Dq = 1.4e-3;
  const V3 n = V3(1, 0.3, -0.2).normalized();
  for (double mu : {0.0, 0.1, 0.6})
    for (double e : {1.0, 0.6}) {
      V3 up(1.0, 0.2, 0.0), wp(0, 30, -10), uq(-0.5, 0.1, 0.3), wq(5, 0, 20);
      const V3 P0 = mp * up + mq * uq;
      // Angular momentum about the contact point (the impulse acts there).
      const V3 c = 0.5 * Dp * n;
      auto L = [&](const V3& u1, const V3& w1, const V3& u2, const V3& w2) {
        const V3 xp = V3::Zero(), xq = 0.5 * (Dp + Dq) * n;
        return V3((xp - c).cross(mp * u1) + 0.1 * mp * Dp * Dp * w1 + (xq - c).cross(mq * u2) +
                  0.1 * mq * Dq * Dq * w2);
      };
      const V3 L0 = L(up, wp, uq, wq);
      const double E0 = 0.5 * mp * up.squaredNorm() + 0.5 * mq * uq.squaredNorm() +
                        0.05 * mp * Dp * Dp * wp.squaredNorm() + 0.05 * mq * Dq * Dq * wq.squaredNorm();
      const double un0 = (up - uq).dot(n);
      collide_pair(up, wp, mp, Dp, uq, wq, mq, Dq, n, {e, mu});
      const V3 P1 = mp * up + mq * uq;
      CHECK((P1 - P0).norm() < 1e-15 * P0.norm() + 1e-20);
      CHECK((L(up, wp, uq, wq) - L0).norm() < 1e-12 * L0.norm());
      CHECK_THAT((up - uq).dot(n), WithinRel(-e * un0, 1e-12));  // restitution of the normal speed
      const double E1 = 0.5 * mp * up.squaredNorm() + 0.5 * mq * uq.squaredNorm() +
                        0.05 * mp * Dp * Dp * wp.squaredNorm() + 0.05 * mq * Dq * Dq * wq.squaredNorm();
      if (e == 1.0 && mu == 0.0) CHECK_THAT(E1, WithinRel(E0, 1e-13));
      CHECK(E1 <= E0 * (1 + 1e-13));
    }
}

TEST_CASE("a wall collision: restitution, and rolling without slip when friction is high", "[dpm]") {
  const V3 n(0, 0, -1);  // the floor, seen from above: the normal points into it
  V3 u(0.3, 0, -1.0), w = V3::Zero();
  collide_wall(u, w, 1e-3, n, {0.5, 0.0});
  CHECK_THAT(u[2], WithinRel(0.5, 1e-14));
  CHECK_THAT(u[0], WithinRel(0.3, 1e-14));
  // Sticking (eq. 3.51): the contact point stops, v_t = 5/7 v_t0, w D / 2 = v_t.
  u = V3(0.3, 0, -1.0);
  w = V3::Zero();
  collide_wall(u, w, 1e-3, n, {0.5, 1.0});
  CHECK_THAT(u[0], WithinRel(5.0 / 7.0 * 0.3, 1e-13));
  const V3 contact = u + 0.5e-3 * w.cross(n);
  CHECK(std::abs(contact[0]) < 1e-14);
}

TEST_CASE("dpm-reference integrates the Stokes response to RK4 accuracy", "[dpm]") {
  // A particle shot at 0.1 m/s into still water with Re_p << 1 (drag
  // correction within 1e-3 of 1): v(t) = v0 exp(-f t / tau_p) with f the
  // (nearly constant) correction; compare against the exact exponential.
  const std::string text = R"(
run: {name: stokes, end_time: 1.0}
domain: {lower: [0, 0, 0], upper: [0.1, 0.1, 0.1], cells: [10, 10, 10]}
gravity: [0, 0, 0]
fluid: {solver: analytic, density: 1000.0, viscosity: 1.0e-6}
particles:
  solver: dpm-reference
  time_step: 1.0e-5
  species:
    bead: {density: 2000.0, diameter: 1.0e-5}
  forces: [drag]
  initial:
    - {single: {species: bead, position: [0.05, 0.05, 0.05], velocity: [1.0e-4, 0, 0]}}
)";
  const auto cfg = coflow::config::parse_config_node(YAML::Load(text), "stokes.yaml", coflow::catalog());
  coflow::particles::ParticleParams params;
  coflow::config::Reader r(cfg.resolved["particles"], "stokes.yaml", "particles");
  params.visit(r, cfg);
  const coflow::coupler::Decomposition dec({10, 10, 10}, 1);
  coflow::particles::DpmReference dpm({cfg, params, dec, 0, MPI_COMM_SELF}, {});
  const double tau = 2000.0 * 1e-10 / (18.0 * 1e-3);  // 11.1 us
  // Re_p = 1e-3: f = 1 + 0.15 Re^0.687 varies with v; integrate the exact ODE
  // dv/dt = -f(v) v / tau by a fine RK4 as the oracle, and check the solver
  // (step 1 us, about tau / 11) against it.
  double v = 1e-4;
  const double h = 1e-8;
  auto rate = [&](double u) { return -(1.0 + 0.15 * std::pow(1000.0 * 1e-5 * u / 1e-3, 0.687)) * u / tau; };
  for (int n = 0; n < 3000; ++n) {
    const double k1 = rate(v), k2 = rate(v + 0.5 * h * k1), k3 = rate(v + 0.5 * h * k2), k4 = rate(v + h * k3);
    v += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  for (int n = 0; n < 30; ++n) dpm.step(1e-6);
  const double got = dpm.particles().v[0];
  CHECK_THAT(got, WithinRel(v, 1e-4));
  CHECK(got < 0.1e-4);  // it did slow down: 30 us ~ 2.7 tau
}

TEST_CASE("collisions apply an impulse only to approaching pairs, and say so", "[dpm]") {
  const V3 n(1, 0, 0);  // from p to q
  V3 up(-0.1, 0, 0), wp = V3::Zero(), uq(0.2, 0, 0), wq = V3::Zero();  // separating
  CHECK_FALSE(collide_pair(up, wp, 1.0, 1e-3, uq, wq, 1.0, 1e-3, n, {0.9, 0.3}));
  CHECK(up == V3(-0.1, 0, 0));
  CHECK(uq == V3(0.2, 0, 0));
  up = V3(0.3, 0, 0);  // approaching
  CHECK(collide_pair(up, wp, 1.0, 1e-3, uq, wq, 1.0, 1e-3, n, {0.9, 0.3}));
  V3 u(0, 0, 1.0), w = V3::Zero();  // leaving the floor
  CHECK_FALSE(collide_wall(u, w, 1e-3, V3(0, 0, -1), {0.5, 0.0}));
  CHECK(u == V3(0, 0, 1.0));
}

TEST_CASE("mean time between collisions of eq. 4.15 from kinetic theory per cell", "[dpm]") {
  // One 1 mm cell holding 8 particles of 0.1 mm moving +-u along x: T = u^2 / 3,
  // f = 4 n D^2 sqrt(pi T) (seed 003 eq. 5.9 per particle, g0 = 1).
  DpmSetup s;
  s.spacing = V3(1e-3, 1e-3, 1e-3);
  s.upper = V3(3e-3, 1e-3, 1e-3);
  s.cells = {3, 1, 1};
  std::vector<V3> x, v;
  std::vector<double> D;
  const double u = 0.2;
  for (int i = 0; i < 8; ++i) {
    x.emplace_back(1e-4 + 1e-4 * i, 5e-4, 5e-4);
    v.emplace_back(i % 2 ? u : -u, 0, 0);
    D.push_back(1e-4);
  }
  // a lone particle in another cell has no partner and sets no time
  x.emplace_back(2.5e-3, 5e-4, 5e-4);
  v.emplace_back(10.0, 0, 0);
  D.push_back(1e-4);
  const double n = 8 / 1e-9, f = 4.0 * n * 1e-8 * std::sqrt(std::numbers::pi * u * u / 3.0);
  const double tau = mean_collision_time(
      x.size(), [&](std::size_t i) { return x[i]; }, [&](std::size_t i) { return v[i]; },
      [&](std::size_t i) { return D[i]; }, s);
  CHECK_THAT(tau, WithinRel(1.0 / f, 1e-12));
  // no spread of velocities: no collisions expected
  for (auto& vi : v) vi = V3(u, 0, 0);
  CHECK(std::isinf(mean_collision_time(
      x.size(), [&](std::size_t i) { return x[i]; }, [&](std::size_t i) { return v[i]; },
      [&](std::size_t i) { return D[i]; }, s)));
}

TEST_CASE("eq. 4.15's collision cells are the cells that decide a particle's rank", "[dpm]") {
  // 5 cells over [0, 0.1]: x = 0.04 lies in cell 2 by (x - lower) / spacing
  // but in cell 1 by the owner's rule (the rank whose block holds cell 1
  // owns it). Counted in cell 2, a particle there and one at x = 0.03 would
  // be in one cell on 1 rank and in two on ranks cut between cells 1 and 2.
  REQUIRE(static_cast<long>(std::floor(0.04 / (0.1 / 5))) == 2);
  CHECK(coflow::particles::store::grid_cell(0.04, 0.0, 0.1, 5) == 1);
  DpmSetup s;
  s.upper = V3(0.1, 0.02, 0.02);
  s.spacing = V3(0.02, 0.02, 0.02);
  s.cells = {5, 1, 1};
  const std::vector<V3> x{V3(0.03, 0.01, 0.01), V3(0.04, 0.01, 0.01)}, v{V3(1.0, 0, 0), V3(-1.0, 0, 0)};
  const double tau = mean_collision_time(
      2, [&](std::size_t i) { return x[i]; }, [&](std::size_t i) { return v[i]; },
      [](std::size_t) { return 1e-3; }, s);
  // one cell of 8e-6 m^3 with 2 particles, T = 1/3 m^2/s^2: f = 4 n D^2 sqrt(pi T)
  const double f = 4.0 * (2.0 / 8e-6) * 1e-6 * std::sqrt(std::numbers::pi / 3.0);
  CHECK_THAT(tau, WithinRel(1.0 / f, 1e-12));
}

TEST_CASE("correlations used beyond their published range are flagged", "[dpm]") {
  FluidSample f;
  f.rho = 1000.0;
  f.mu = 1e-3;
  const ForceSet all{};
  const double D = 1e-3;
  // Re_p = rho D |u - v| / mu = 50, a shear giving beta = Re_s / (2 Re_p) = 0.1: every term in range.
  f.vorticity = V3(0, 0, 10.0);  // Re_s = rho D^2 |omega| / mu = 10
  FluidLoad L = fluid_load(f, D, V3(0.05, 0, 0), V3(0, 0, 1.0), all);
  CHECK(L.beyond == 0u);
  // beta = 10 / (2 x 500) = 0.01 still in; at Re_p 5000, beta = 0.001: Saffman-Mei beyond, and Magnus beyond Re_p 140.
  L = fluid_load(f, D, V3(5.0, 0, 0), V3(0, 0, 1.0), all);
  CHECK((L.beyond & kSaffmanBeta) != 0u);
  CHECK((L.beyond & kMagnusReP) != 0u);
  CHECK((L.beyond & kRotationReR) == 0u);
  // Re_r = rho D^2 |omega_rel| / mu = 2000: the rotational coefficient beyond 1000.
  L = fluid_load(f, D, V3(0.05, 0, 0), V3(0, 0, 2005.0), all);
  CHECK((L.beyond & kRotationReR) != 0u);
}

TEST_CASE("eq. 4.15's cell-crossing time takes the fluid cells' narrowest side", "[dpm]") {
  // Cells of 10 x 2.5 mm (fv allows non-cubic cells); a particle at 1 m/s
  // along y, no drag: 0.2 x 2.5 mm / (1 m/s) = 0.5 ms, not 0.2 x 10 mm / (1 m/s).
  const std::string text = R"(
run: {name: cross, end_time: 0.01}
domain: {lower: [0, 0, 0], upper: [0.1, 0.1, 0.1], cells: [10, 40, 1]}
gravity: [0, 0, 0]
fluid: {solver: analytic, density: 1.2, viscosity: 1.5e-5}
particles:
  solver: dpm
  time_step: auto
  species:
    bead: {density: 2000.0, diameter: 1.0e-4}
  forces: []
  initial:
    - {single: {species: bead, position: [0.05, 0.01, 0.05], velocity: [0, 1.0, 0]}}
)";
  const auto cfg = coflow::config::parse_config_node(YAML::Load(text), "cross.yaml", coflow::catalog());
  coflow::particles::ParticleParams params;
  coflow::config::Reader r(cfg.resolved["particles"], "cross.yaml", "particles");
  params.visit(r, cfg);
  const auto s = coflow::particles::dpm::make_setup(params, cfg);
  FluidSample still;
  CHECK_THAT(lagrangian_step(s, 1e-4, 2000.0, V3(0, 1.0, 0), still), WithinRel(5e-4, 1e-12));
  CHECK_THAT(lagrangian_step(s, 1e-4, 2000.0, V3(2.0, 0, 0), still),
             WithinRel(2.5e-4, 1e-12));  // the same side
  // A 2D grid's depth (one cell, here 1 mm thin) is no cell to cross.
  std::string thin = text;
  thin.replace(thin.find("upper: [0.1, 0.1, 0.1]"), 22, "upper: [0.1, 0.1, 0.001]");
  thin.replace(thin.find("[0.05, 0.01, 0.05]"), 18, "[0.05, 0.01, 5e-4]");
  const auto cfg2 = coflow::config::parse_config_node(YAML::Load(thin), "thin.yaml", coflow::catalog());
  coflow::particles::ParticleParams params2;
  coflow::config::Reader r2(cfg2.resolved["particles"], "thin.yaml", "particles");
  params2.visit(r2, cfg2);
  const auto s2 = coflow::particles::dpm::make_setup(params2, cfg2);
  CHECK_THAT(lagrangian_step(s2, 1e-4, 2000.0, V3(0, 1.0, 0), still), WithinRel(5e-4, 1e-12));
}

TEST_CASE("an inlet's probe lattice covers its face, and a point takes its nearest probe", "[dpm]") {
  Inlet in;
  in.center = V3(0.05, 0.05, 0.0);
  in.normal = V3(0.0, 0.0, 1.0);
  basis(in.normal, V3::Zero(), in.t1, in.t2);
  in.radius = 0.01;
  set_probe_lattice(in, 0.004);  // half a 4 mm cell apart: 2 mm, 5 either side of the centre
  CHECK(in.probe_step == 0.002);
  CHECK(probe_count(in) == 11u * 11u);
  for (std::size_t q = 0; q < probe_count(in); ++q) {
    const V3 x = probe_point(in, q);
    CHECK(nearest_probe(in, x) == q);
    CHECK(std::abs(x.z()) <= 0.0);  // on the face's plane
  }
  // A point of the face is within half a diagonal of its probe.
  for (int k = 0; k < 200; ++k) {
    const double r = in.radius * std::sqrt((k + 0.5) / 200.0), phi = 2.4 * k;
    const V3 p = in.center + r * (std::cos(phi) * in.t1 + std::sin(phi) * in.t2);
    CHECK((probe_point(in, nearest_probe(in, p)) - p).norm() <=
          in.probe_step * std::sqrt(0.5) * (1.0 + 1e-12));
  }
  // A wide rectangle: at most 16 steps either side of the centre.
  Inlet wide = in;
  wide.disk = false;
  wide.a = 1.0;
  wide.b = 0.01;
  set_probe_lattice(wide, 0.004);
  CHECK(wide.probe_n[0] == 16);
  CHECK(wide.probe_step == 1.0 / 32.0);
  CHECK(probe_count(wide) <= 33u * 33u);
}

TEST_CASE(
    "a particle entering through either of two inlets takes the sample of its own inlet's nearest probe",
    "[dpm]") {
  // A disk on z = 0 and a rectangle on x = 0; each probe's row carries its
  // own position as the velocity, so the row a particle takes says where it
  // was sampled.
  std::vector<Inlet> inlets(2);
  inlets[0].center = V3(0.05, 0.05, 0.0);
  inlets[0].normal = V3(0.0, 0.0, 1.0);
  inlets[0].radius = 0.01;
  inlets[1].disk = false;
  inlets[1].center = V3(0.0, 0.03, 0.06);
  inlets[1].normal = V3(1.0, 0.0, 0.0);
  inlets[1].a = 0.02;
  inlets[1].b = 0.006;
  for (Inlet& in : inlets) {
    basis(in.normal, V3::Zero(), in.t1, in.t2);
    set_probe_lattice(in, 0.004);
  }
  const auto points = ProbeFluid::points(inlets);
  REQUIRE(points.size() == ProbeFluid::count(inlets));
  std::vector<double> rows(points.size() * coflow::particles::ParticleSolver::kFluidValues, 0.0);
  for (std::size_t q = 0; q < points.size(); ++q)
    for (int d = 0; d < 3; ++d) rows[q * coflow::particles::ParticleSolver::kFluidValues + d] = points[q][d];
  ProbeFluid probes;
  FluidSample still;
  still.rho = 1.0;
  CHECK(probes.at(inlets, 1, inlets[1].center, still).rho == 1.0);  // nothing sampled yet: at rest
  CHECK_THROWS_AS(probes.set(rows, points.size() + 1), std::runtime_error);
  probes.set(rows, points.size());
  for (std::size_t k = 0; k < 2; ++k) {
    const Inlet& in = inlets[k];
    for (int j = 0; j < 100; ++j) {
      const double s1 = std::sin(1.3 * j), s2 = std::cos(2.9 * j);  // spread over [-1, 1]^2
      const V3 p = in.center + s1 * (in.disk ? in.radius : 0.5 * in.a) * std::sqrt(0.5) * in.t1 +
                   s2 * (in.disk ? in.radius : 0.5 * in.b) * std::sqrt(0.5) * in.t2;
      const V3 u = probes.at(inlets, k, p, still).u;
      CHECK((u - probe_point(in, nearest_probe(in, p))).norm() <= 0.0);
      CHECK(std::abs((u - in.center).dot(in.normal)) <= 1e-15);  // on this inlet's face
      CHECK((u - p).norm() <= in.probe_step * std::sqrt(0.5) * (1.0 + 1e-12));
    }
  }
}

TEST_CASE("an inlet across a periodic face injects into the domain, clear of its neighbours' images",
          "[dpm]") {
  // A 20 mm disk centred 1 mm from x = 0 of a box periodic along x (0.1 m):
  // most of it lies past the face, over the images of particles packed
  // against x = 0.1 m. Entering particles must come out wrapped into
  // [0, 0.1) and overlap no neighbour's nearest image.
  Inlet in;
  in.species = 0;
  in.density = 2500.0;
  in.diameter.a = 1e-3;
  in.dmax = 1e-3;
  in.mass_flow = 2500.0 * std::numbers::pi / 6.0 * 1e-9 * 400.0;  // 400 particles owed in a step of 1 s
  in.speed = 1e-3;
  in.center = V3(0.001, 0.05, 0.0);
  in.normal = V3(0.0, 0.0, 1.0);
  in.dir = in.normal;
  basis(in.normal, V3::Zero(), in.t1, in.t2);
  in.radius = 0.01;
  in.period = V3(0.1, 0.0, 0.0);
  std::vector<std::pair<V3, double>> nearby;
  for (int i = 0; i < 10; ++i)  // a wall of particles along y just inside x = 0.1 m
    for (int j = 0; j < 20; ++j)
      nearby.emplace_back(V3(0.0995 - 0.001 * (i % 2), 0.04 + 0.001 * j, 0.0005 * i), 1e-3);
  const std::size_t given = nearby.size();
  std::vector<Entering> out;
  inject(in, 0, 7, 0.0, 1.0, nearby, out);
  REQUIRE(out.size() > 100u);
  for (const Entering& e : out) {
    CHECK(e.x.x() >= 0.0);
    CHECK(e.x.x() < 0.1);
    for (std::size_t k = 0; k < given; ++k)
      CHECK(nearest_image(nearby[k].first - e.x, in.period).norm() >= 1e-3 * (1.0 - 1e-12));
  }
}
