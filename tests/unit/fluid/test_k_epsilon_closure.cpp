// The two-layer k-epsilon closure (seed 003 eqs. 3.17-3.25) against its
// limits: the blending width of eq. 3.25, the viscous sublayer's epsilon, and
// the log layer, where the one-equation layer must give Prandtl's mixing
// length nu_t = kappa u_tau y and epsilon = u_tau^3 / (kappa y) for the
// equilibrium k = u_tau^2 / sqrt(C_mu) (Pope 2000 §7.3, §10.4).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "fluid/fv/turbulence/closure.hpp"

using coflow::fluid::fv::Closure;

TEST_CASE("the default constants are the seed's (seed 003 §3.1.2, text after eqs. 3.14 and 3.22)",
          "[fv][turbulence]") {
  // Launder & Sharma 1974 as the seed quotes them: sigma_k 1.0, sigma_epsilon
  // 1.3, C_epsilon1 1.44, C_epsilon2 1.92, C_mu 0.09; C_l = 0.4187 C_mu^-3/4,
  // A_mu = 70, A_epsilon = 2 C_l; Re_y* = 200.
  const coflow::fluid::TurbulenceConstants c;
  CHECK(c.sigma_k == 1.0);
  CHECK(c.sigma_epsilon == 1.3);
  CHECK(c.C_epsilon1 == 1.44);
  CHECK(c.C_epsilon2 == 1.92);
  CHECK(c.C_mu == 0.09);
  CHECK(c.A_mu == 70.0);
  CHECK(c.Re_y_star == 200.0);
  CHECK(c.C_l() == Approx(0.4187 * std::pow(0.09, -0.75)).epsilon(1e-15));
  CHECK(c.C_l() == Approx(2.5481).epsilon(1e-4));  // 0.4187 / 0.16432
  CHECK(c.A_epsilon() == Approx(2.0 * c.C_l()).epsilon(1e-15));
}

TEST_CASE("two-layer blending: one half at Re_y*, 0.01 and 0.99 at 0.8 and 1.2 Re_y* (eq. 3.25)", "[fv][turbulence]") {
  const Closure cl{{}, 1e-5, true};
  const double star = cl.c.Re_y_star;
  CHECK(cl.blend(star) == Approx(0.5).epsilon(1e-14));
  CHECK(cl.blend(1.2 * star) == Approx(0.99).epsilon(1e-12));
  CHECK(cl.blend(0.8 * star) == Approx(0.01).epsilon(1e-10));
}

TEST_CASE("two-layer: epsilon tends to 2 nu k / y^2 at the wall (A_epsilon = 2 C_l)", "[fv][turbulence]") {
  const Closure cl{{}, 1e-5, true};
  const double k = 1e-4;
  for (double y : {1e-6, 1e-7}) {
    const double limit = 2 * cl.nu * k / (y * y);
    CHECK(cl.epsilon_near_wall(y, k) == Approx(limit).epsilon(2e-3 * y / 1e-6));
  }
}

TEST_CASE("two-layer: the log layer's mixing length and dissipation", "[fv][turbulence]") {
  const Closure cl{{}, 1e-6, true};
  const double utau = 0.05, k = utau * utau / std::sqrt(cl.c.C_mu);
  const double y = 0.05;  // y+ = 2500: Re_y far above A_mu and A_epsilon
  const double rey = cl.re_y(y, k);
  REQUIRE(rey > 50 * cl.c.A_mu);  // exp(-Re_y / A_mu) < 1e-28
  CHECK(cl.c.C_mu * cl.l_mu(y, rey) * std::sqrt(k) == Approx(cl.c.kappa * utau * y).epsilon(1e-12));
  CHECK(cl.epsilon_near_wall(y, k) == Approx(utau * utau * utau / (cl.c.kappa * y)).epsilon(1e-12));
  // And k-epsilon's own nu_t there agrees: C_mu k^2 / epsilon = kappa u_tau y.
  const double eps = utau * utau * utau / (cl.c.kappa * y);
  CHECK(cl.nu_t(std::numeric_limits<double>::infinity(), k, eps) == Approx(cl.c.kappa * utau * y).epsilon(1e-12));
  // Far beyond Re_y* the blend is the standard model's.
  CHECK(cl.nu_t(y, k, eps) == Approx(cl.c.C_mu * k * k / eps).epsilon(1e-12));
}

TEST_CASE("without walls, or without the wall model, nu_t = C_mu k^2 / epsilon (eq. 3.17)", "[fv][turbulence]") {
  const Closure walls{{}, 1e-5, true}, plain{{}, 1e-5, false};
  CHECK(walls.nu_t(std::numeric_limits<double>::infinity(), 2.0, 3.0) == Approx(0.09 * 4.0 / 3.0));
  CHECK(plain.nu_t(1e-4, 2.0, 3.0) == Approx(0.09 * 4.0 / 3.0));
  CHECK_FALSE(plain.one_equation(1e-6, 1e-8));
  CHECK(walls.one_equation(1e-6, 1e-8));
}

// The row forms that fv's loops call (vectorised, the exponentials by
// glibc's vector exp, which passes a 4-ulp criterion) give the per-cell
// numbers (std::exp) within the exponentials' error as the formulas carry it:
// a relative error r in exp(-x) becomes r exp(-x) / (1 - exp(-x)) in the
// length scales' 1 - exp(-x), large near a wall (x = Re_y / A small); in the
// blend lambda = 1 / (1 + exp(x)) it moves lambda by at most r / 4, or by
// half an ulp where 1 + exp(x) rounds the other way, and nu_t by that times
// |standard - two-layer| (the two viscosities lambda blends). Cells across
// the blending layer, in the one-equation layer, beyond 20 blending widths,
// at a wall distance of infinity (no walls), and with the standard model
// alone; where no exponential is used (the standard model alone, epsilon
// outside the one-equation layer, which cells are in it) the same bits.
// Measured: at most 0.12 of that bound (the bound takes 8 ulp for r).
TEST_CASE("nu_t_row and near_wall_row agree with nu_t, one_equation and epsilon_near_wall per cell",
          "[fv][turbulence]") {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> y, k, eps;
  for (int i = 0; i < 203; ++i) {  // not a multiple of a vector's width: the loops' tails too
    y.push_back(i % 17 == 5 ? inf : 1e-5 * std::pow(1.09, i));
    k.push_back(1e-3 * (1.0 + 0.3 * std::sin(0.7 * i)));
    eps.push_back(2e-3 * (1.0 + 0.5 * std::cos(0.3 * i)));
  }
  const long n = static_cast<long>(y.size());
  for (bool two_layer : {true, false}) {
    const Closure cl{{}, 1.5e-5, two_layer};
    std::vector<double> nut(y.size()), e = eps, fixed(y.size()), work(3 * y.size());
    cl.nu_t_row(y.data(), k.data(), eps.data(), nut.data(), n, work.data());
    cl.near_wall_row(y.data(), k.data(), e.data(), fixed.data(), n, work.data());
    int blended = 0, one_equation = 0;
    double worst = 0.0;  // the largest difference over its bound
    for (std::size_t i = 0; i < y.size(); ++i) {
      const double rey = cl.re_y(y[i], k[i]);
      const double ulps = 8 * std::numeric_limits<double>::epsilon();  // 4 ulp, and the rounding after
      const auto amplified = [&](double x) { return ulps * (1.0 + std::exp(-x) / -std::expm1(-x)); };
      const double nut_cell = cl.nu_t(y[i], k[i], eps[i]);
      const double e_cell = fixed[i] > 0 ? cl.epsilon_near_wall(y[i], k[i]) : eps[i];
      const double standard = cl.c.C_mu * k[i] * k[i] / eps[i];
      const double layer = cl.c.C_mu * cl.l_mu(y[i], rey) * std::sqrt(k[i]);
      const double blend_error = ulps * std::abs(standard - layer) / nut_cell;
      const double dn = std::abs(nut[i] - nut_cell) / ((amplified(rey / cl.c.A_mu) + blend_error) * nut_cell);
      const double de = std::abs(e[i] - e_cell) / (amplified(rey / cl.A_epsilon) * e_cell);
      worst = std::max({worst, dn, de});
      CHECK(dn <= 1.0);
      CHECK(de <= 1.0);
      const bool standard_alone = !two_layer || !(y[i] < inf) ||
                                  (rey - cl.c.Re_y_star) * Closure::kAtanh098 > 20 * 0.2 * cl.c.Re_y_star;
      if (standard_alone) CHECK(std::abs(nut[i] - nut_cell) <= 0);
      if (fixed[i] == 0.0) CHECK(std::abs(e[i] - eps[i]) <= 0);
      CHECK(fixed[i] == (cl.one_equation(y[i], k[i]) ? 1.0 : 0.0));
      blended += nut[i] != cl.c.C_mu * k[i] * k[i] / eps[i];
      one_equation += fixed[i] > 0;
    }
    INFO("largest difference over its bound " << worst);
    CHECK(worst < 1.0);
    // The cases the loop must cover are there (with the wall model).
    CHECK((blended > 20) == two_layer);
    CHECK((one_equation > 20) == two_layer);
    CHECK(one_equation < n - 20);
  }
}

// The wall functions (wall: log-law) against the log law they encode (Pope
// 2000 §7.1.4, §10.4; Launder & Spalding 1974): for the equilibrium k =
// u_tau^2 / sqrt(C_mu) and the log law's speed U = u_tau ln(E y+) / kappa the
// wall's shear is u_tau^2, the production tau_w dU/dy equals epsilon = u_tau^3
// / (kappa y), and nu_t = C_mu k^2 / epsilon is kappa u_tau y; below y*_lam
// the shear is the viscous nu U / y.
TEST_CASE("wall functions: the log law's shear, production and epsilon; y*_lam", "[fv][turbulence]") {
  using coflow::fluid::fv::WallFunction;
  const WallFunction wf{{}, 1e-5};
  // y*_lam solves y = ln(E y) / kappa: 11.53 for kappa 0.41, E 9.8.
  CHECK(std::log(wf.c.log_E * wf.y_lam) / wf.c.log_kappa == Approx(wf.y_lam).epsilon(1e-14));
  CHECK(wf.y_lam == Approx(11.53).margin(0.01));
  const double utau = 0.2, k = utau * utau / std::sqrt(wf.c.C_mu);
  for (double yplus : {30.0, 100.0, 500.0}) {
    const double y = yplus * wf.nu / utau;
    CHECK(wf.y_star(y, k) == Approx(yplus).epsilon(1e-14));
    const double U = utau * std::log(wf.c.log_E * yplus) / wf.c.log_kappa;
    CHECK(wf.nu_wall(y, k) * U / y == Approx(utau * utau).epsilon(1e-13));
    const double eps = utau * utau * utau / (wf.c.log_kappa * y);
    CHECK(wf.epsilon(y, k) == Approx(eps).epsilon(1e-13));
    CHECK(wf.production(y, k, U) == Approx(eps).epsilon(1e-13));
    CHECK(wf.c.C_mu * k * k / wf.epsilon(y, k) == Approx(wf.c.log_kappa * utau * y).epsilon(1e-13));
  }
  // In the viscous sublayer: nu_w = nu, so the shear is nu U / y, k's
  // production that shear times the log law's slope C_mu^1/4 k^1/2 / (kappa
  // y) (OpenFOAM's epsilonLowReWallFunction), and epsilon 2 nu k / y^2.
  const double y = 5.0 * wf.nu / utau, U = 5.0 * utau;
  REQUIRE(wf.y_star(y, k) < wf.y_lam);
  CHECK(wf.nu_wall(y, k) == wf.nu);
  CHECK(wf.production(y, k, U) == Approx(wf.nu * (U / y) * utau / (wf.c.log_kappa * y)).epsilon(1e-14));
  CHECK(wf.epsilon(y, k) == Approx(2 * wf.nu * k / (y * y)).epsilon(1e-14));
}
