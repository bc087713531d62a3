// The pointwise closure of the k-epsilon model with the two-layer wall
// treatment (seed 003 eqs. 3.17-3.25): the eddy viscosity from k, epsilon and
// the wall distance, and epsilon in the one-equation layer near a wall.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "fluid/fv/turbulence/exponentials.hpp"
#include "fluid/turbulence_params.hpp"

namespace coflow::fluid::fv {

// The rows' exponents are held above this: exp(-700) is a normal number
// (the vector exp would take its slow scalar path for an underflow), and
// 1 - exp(-700) and 1 / (1 + exp(-700)) are 1, as they are with exp of less.
inline constexpr double kLowestExponent = -700.0;

// The source terms of one cell (seed 003 eqs. 3.13-3.14) from the old nu_t,
// S^2, k and epsilon: production P = nu_t S^2 (explicit), the destruction
// rates linearised about the old values (implicit: epsilon / k for k, C_e2
// epsilon / k for epsilon) and epsilon's production C_e1 (epsilon / k) P.
struct Sources {
  double production, sink_k, sink_epsilon, source_epsilon;
};
inline Sources sources(const TurbulenceConstants& c, double nu_t, double s2, double k, double eps) {
  const double P = nu_t * s2, rate = eps / k;
  return {P, rate, c.C_epsilon2 * rate, c.C_epsilon1 * rate * P};
}

struct Closure {
  TurbulenceConstants c;
  double nu = 1e-6;         // molecular kinematic viscosity, m^2/s
  bool two_layer = true;
  // Wolfshtein's constants, computed once (C_l is a pow, and these are
  // evaluated per cell and step).
  double C_l = c.C_l(), A_epsilon = c.A_epsilon();

  // Re_y = y sqrt(k) / nu (eq. 3.20); infinite without walls.
  double re_y(double y, double k) const { return y * std::sqrt(k) / nu; }
  // lambda_epsilon (eqs. 3.24-3.25): 0 at a wall, 1 far from it.
  static constexpr double kAtanh098 = 2.2975599250672945;  // atanh(0.98)
  double blend(double rey) const {
    const double A = 0.2 * c.Re_y_star / kAtanh098;
    // 0.5 (1 + tanh x) = 1 / (1 + exp(-2x)): one exponential (the tanh, about
    // twice as dear, was 2 % of a k-epsilon step in bench-fv's channel).
    return 1.0 / (1.0 + std::exp(-2.0 * (rey - c.Re_y_star) / A));
  }
  // Wolfshtein's length scales (eqs. 3.19, 3.22).
  double l_mu(double y, double rey) const { return y * C_l * (1.0 - std::exp(-rey / c.A_mu)); }
  double l_epsilon(double y, double rey) const {
    return y * C_l * (1.0 - std::exp(-rey / A_epsilon));
  }
  // A cell of the one-equation layer: its epsilon is eq. 3.18's, not the
  // transport equation's.
  bool one_equation(double y, double k) const { return two_layer && re_y(y, k) < c.Re_y_star; }
  // epsilon = k^3/2 / l_epsilon (eq. 3.18); near the wall 2 nu k / y^2 (A_epsilon = 2 C_l).
  double epsilon_near_wall(double y, double k) const {
    const double rey = re_y(y, k);
    const double l = l_epsilon(y, rey);
    return l > 0 ? k * std::sqrt(k) / l : 2.0 * nu * k / (y * y);
  }
  // Over n cells: fixed 1 in the one-equation layer, with epsilon set to
  // epsilon_near_wall there, and 0 elsewhere (one_equation and
  // epsilon_near_wall per cell, the exponentials by the vector exp), in three
  // vectorised passes (work: 2 n doubles).
  void near_wall_row(const double* y, const double* k, double* eps, double* fixed, long n,
                     double* work) const {
    double* __restrict rey = work, * __restrict e = work + n;
    long layer = 0;  // cells in the one-equation layer (an integer sum: it vectorises)
    for (long i = 0; i < n; ++i) {
      rey[i] = re_y(y[i], k[i]);
      fixed[i] = two_layer && rey[i] < c.Re_y_star ? 1.0 : 0.0;
      layer += two_layer && rey[i] < c.Re_y_star ? 1 : 0;
    }
    if (layer == 0) return;  // eps as it is: no exponential needed
    for (long i = 0; i < n; ++i) e[i] = std::max(-rey[i] / A_epsilon, kLowestExponent);
    exp_in_place(e, n);  // every cell of a row that needs some (a vector exp is cheaper than a test)
    for (long i = 0; i < n; ++i) {
      const double l = y[i] * C_l * (1.0 - e[i]);
      const double near = l > 0 ? k[i] * std::sqrt(k[i]) / l : 2.0 * nu * k[i] / (y[i] * y[i]);
      eps[i] = fixed[i] > 0 ? near : eps[i];
    }
  }
  // nu_t: C_mu k^2 / epsilon (eq. 3.17) blended with C_mu l_mu sqrt(k) (eq.
  // 3.21) by lambda_epsilon (eq. 3.23).
  double nu_t(double y, double k, double eps) const {
    const double standard = c.C_mu * k * k / eps;
    if (!two_layer || !(y < std::numeric_limits<double>::infinity())) return standard;
    const double rey = re_y(y, k);
    // tanh is exactly 1 in double beyond 20 widths: the standard model alone
    // (the same number, without the exponentials).
    if ((rey - c.Re_y_star) * kAtanh098 > 20 * 0.2 * c.Re_y_star) return standard;
    const double lambda = blend(rey);
    return lambda * standard + (1.0 - lambda) * c.C_mu * l_mu(y, rey) * std::sqrt(k);
  }
  // nu_t() of the n cells of a row into out (the exponentials by the vector
  // exp), in three vectorised passes: the exponentials' arguments and where
  // the blend is needed, the exponentials, the blend (work: 3 n doubles).
  void nu_t_row(const double* y, const double* k, const double* eps, double* out, long n,
                double* work) const {
    double* __restrict near = work, * __restrict ea = work + n, * __restrict eb = work + 2 * n;
    const double A = 0.2 * c.Re_y_star / kAtanh098, cut = 20 * 0.2 * c.Re_y_star;
    const double inf = std::numeric_limits<double>::infinity();
    long blend_cells = 0;  // an integer sum: it vectorises
    for (long i = 0; i < n; ++i) {
      const double rey = re_y(y[i], k[i]);
      const bool blended = two_layer && y[i] < inf && !((rey - c.Re_y_star) * kAtanh098 > cut);
      near[i] = blended ? 1.0 : 0.0;
      blend_cells += blended ? 1 : 0;
      ea[i] = std::max(-2.0 * (rey - c.Re_y_star) / A, kLowestExponent);
      eb[i] = std::max(-rey / c.A_mu, kLowestExponent);
    }
    if (blend_cells > 0) {  // every cell of a row that needs some (a vector exp is cheaper than a test)
      exp_in_place(ea, n);
      exp_in_place(eb, n);
    }
    for (long i = 0; i < n; ++i) {
      const double standard = c.C_mu * k[i] * k[i] / eps[i];
      const double lambda = 1.0 / (1.0 + ea[i]), l_mu = y[i] * C_l * (1.0 - eb[i]);
      const double blended = lambda * standard + (1.0 - lambda) * c.C_mu * l_mu * std::sqrt(k[i]);
      out[i] = near[i] > 0 ? blended : standard;
    }
  }
};

// y+ of a cell that borders several walls: the largest (the wall that limits
// the resolution); a NaN is kept, so that no check reads past it.
inline void keep_largest(double& y_plus, double candidate) {
  if (candidate > y_plus || candidate != candidate) y_plus = candidate;
}

// Wall functions (wall: log-law; Launder & Spalding 1974, in the k-based
// form that stays defined where the wall's shear vanishes, at separation and
// reattachment): in a cell whose centre lies y from a wall, y* = C_mu^1/4
// k^1/2 y / nu; above y*_lam, where the linear and log laws meet, the wall's
// shear is tau_w = kappa C_mu^1/4 k^1/2 U / ln(E y*) (U the tangential speed
// relative to the wall), below it nu U / y. Not the seed's model (seed 003
// takes the two-layer one); for walls whose first cells lie in the log layer.
struct WallFunction {
  TurbulenceConstants c;
  double nu = 1e-6;  // molecular kinematic viscosity, m^2/s
  double C_mu_quarter = std::pow(c.C_mu, 0.25);
  double y_lam = c.log_law_y_lam();  // 11.53 for kappa 0.41, E 9.8 (validated finite)
  double y_star(double y, double k) const { return C_mu_quarter * std::sqrt(k) * y / nu; }
  // The wall face's viscosity nu_w = tau_w y / U: the wall's shear is
  // nu_w U / y whatever U (the k-based law is linear in U).
  double nu_wall(double y, double k) const {
    const double ys = y_star(y, k);
    return ys > y_lam ? nu * ys * c.log_kappa / std::log(c.log_E * ys) : nu;
  }
  // epsilon of the cell: C_mu^3/4 k^3/2 / (kappa y) in the log layer (the
  // equilibrium of production and dissipation), 2 nu k / y^2 below y*_lam
  // (the wall limit of eq. 3.18's).
  double epsilon(double y, double k) const {
    if (y_star(y, k) > y_lam)
      return C_mu_quarter * C_mu_quarter * C_mu_quarter * k * std::sqrt(k) / (c.log_kappa * y);
    return 2.0 * nu * k / (y * y);
  }
  // The production of k in the cell, tau_w dU/dy with the log law's slope
  // C_mu^1/4 k^1/2 / (kappa y), tau_w the wall's shear of either law (as the
  // G of OpenFOAM's epsilonLowReWallFunction: (nu_t,w + nu) |dU/dn|_w C_mu^1/4
  // k^1/2 / (kappa y) in both).
  double production(double y, double k, double U) const {
    return nu_wall(y, k) * U / y * (C_mu_quarter * std::sqrt(k) / (c.log_kappa * y));
  }
};

}  // namespace coflow::fluid::fv
