// fluid.turbulence: the URANS closure of the fv fluid (seed 003 §3.1.2, the wall layer §3.1.2.1): the
// standard k-epsilon model (eqs. 3.13-3.17, Launder & Sharma 1974 constants)
// with the two-layer near-wall model (eqs. 3.18-3.25). Part of the fluid
// schema library; the model itself is fluid/fv/turbulence/.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "coflow/config.hpp"

namespace coflow::fluid {

struct TurbulenceConstants {
  double sigma_k = 1.0, sigma_epsilon = 1.3, C_epsilon1 = 1.44, C_epsilon2 = 1.92, C_mu = 0.09;
  // The two-layer model (eqs. 3.19-3.25): C_l = kappa C_mu^-3/4 with kappa
  // 0.4187, A_mu = 70, A_epsilon = 2 C_l, Re_y* = 200.
  double kappa = 0.4187, A_mu = 70.0, Re_y_star = 200.0;
  // The wall functions (wall: log-law): the log law's kappa and E (Launder &
  // Spalding 1974; 0.41 and 9.8, as OpenFOAM's nutkWallFunction).
  double log_kappa = 0.41, log_E = 9.8;
  double C_l() const { return kappa * std::pow(C_mu, -0.75); }
  // The log law's y*_lam, where the linear and log laws meet: the root of
  // g(y) = ln(E y) / kappa - y above 1 / kappa (11.53 for kappa 0.41, E 9.8).
  // g is concave and falls beyond 1 / kappa, so Newton's method from y = 1e4
  // (where g < 0) falls monotonically onto that root. NaN where there is none
  // (E at most e kappa: g < 0 everywhere) or Newton has not settled.
  double log_law_y_lam() const {
    double y = 1e4;
    for (int i = 0; i < 100 && y > 1.0 / log_kappa; ++i)
      y -= (std::log(log_E * y) / log_kappa - y) / (1.0 / (log_kappa * y) - 1.0);
    const bool root = y > 1.0 / log_kappa && std::abs(std::log(log_E * y) / log_kappa - y) <= 1e-12 * y;
    return root ? y : std::nan("");
  }
  double A_epsilon() const { return 2.0 * C_l(); }
  void visit(config::Visitor& v) {
    v("sigma_k", sigma_k, "turbulent Prandtl number of k (eq. 3.13)", config::greater(0.0));
    v("sigma_epsilon", sigma_epsilon, "turbulent Prandtl number of epsilon (eq. 3.14)", config::greater(0.0));
    v("C_epsilon1", C_epsilon1, "production coefficient of epsilon (eq. 3.14)", config::greater(0.0));
    v("C_epsilon2", C_epsilon2,
      "destruction coefficient of epsilon (eq. 3.14); decaying turbulence falls as t^(-1/(C_epsilon2 - 1))",
      config::greater(1.0));
    v("C_mu", C_mu, "eddy-viscosity coefficient (eq. 3.17)", config::greater(0.0));
    v("kappa", kappa, "two-layer: C_l = kappa C_mu^(-3/4) (eqs. 3.19, 3.22)", config::greater(0.0));
    v("A_mu", A_mu, "two-layer: damping Reynolds number of l_mu (eq. 3.22)", config::greater(0.0));
    v("log_kappa", log_kappa, "log-law: von Karman's constant of u+ = ln(E y+) / kappa",
      config::greater(0.0));
    v("log_E", log_E, "log-law: the constant E of u+ = ln(E y+) / kappa (smooth walls)",
      config::greater(1.0));
    v("Re_y_star", Re_y_star,
      "two-layer: the wall-distance Reynolds number that parts the one-equation layer from the k-epsilon region "
      "(eqs. 3.20, 3.24)",
      config::greater(0.0));
  }
};

struct TurbulenceParams {
  // nu_t = C_mu k^2 / epsilon (eq. 3.17) and the rate epsilon / k of the
  // destruction terms (eqs. 3.13-3.14) of a k and epsilon just read must be
  // finite numbers: a huge k or a tiny epsilon overflows the first, a tiny k
  // beside a large epsilon the second (the first step would then stop on a
  // value that is not finite).
  void finite_eddy_viscosity(config::Visitor& s, double k, double epsilon) const {
    if (!s.reading() || !(k > 0 && epsilon > 0)) return;  // a value that is not positive has its own message
    if (!std::isfinite(constants.C_mu * k * k / epsilon))
      s.fail("epsilon",
             fmt::format("nu_t = C_mu k^2 / epsilon = {} * {:g}^2 / {:g} is not a finite number; give "
                         "k and epsilon of a real flow (nu_t = C_mu k^2 / epsilon, m^2/s)",
                         constants.C_mu, k, epsilon));
    if (!std::isfinite(epsilon / k))
      s.fail("epsilon", fmt::format("the rate epsilon / k = {:g} / {:g} is not a finite number; give k and "
                                    "epsilon of a real flow (epsilon / k is 1 / the eddies' time scale, 1/s)",
                                    epsilon, k));
  }

  bool on = false;  // the section is given
  std::string model = "k-epsilon";
  std::string wall = "two-layer";
  TurbulenceConstants constants;
  double initial_k = 0.0, initial_epsilon = 0.0;  // m^2/s^2, m^2/s^3
  double inlet_k = 0.0, inlet_epsilon = 0.0;      // at velocity faces
  bool inlet_given = false;
  void visit(config::Visitor& v) {
    v("model", model, "the closure: k-epsilon (standard, eqs. 3.13-3.17)", config::one_of({"k-epsilon"}));
    v("wall", wall,
      "near-wall treatment: two-layer (Wolfshtein's one-equation layer blended by Re_y, eqs. 3.18-3.25; the "
      "first cells at y+ of about 1), log-law (wall functions of Launder & Spalding 1974, not the seed's: "
      "the "
      "wall's shear, epsilon and the production of k in the cells next to a wall from the log law with y* = "
      "C_mu^1/4 k^1/2 y / nu; the first cell centres at y+ of 30 to 100) or none (a box without walls)",
      config::one_of({"two-layer", "log-law", "none"}));
    v.section(
        "constants", "model constants (Launder & Sharma 1974; seed 003 §3.1.2)", [&](config::Visitor& s) {
          constants.visit(s);
          if (s.reading() && wall == "log-law" && !std::isfinite(constants.log_law_y_lam()))
            s.fail("log_E",
                   fmt::format("the log law u+ = ln(E y+) / kappa with E = {} and kappa = {} never meets "
                               "u+ = y+ (E must exceed e kappa = {:.3g}); the usual values are E 9.8, "
                               "kappa 0.41",
                               constants.log_E, constants.log_kappa, std::exp(1.0) * constants.log_kappa));
        });
    v.section("initial", "uniform initial turbulence", [&](config::Visitor& s) {
      s.required("k", initial_k, "turbulence kinetic energy, m^2/s^2", config::greater(0.0));
      s.required("epsilon", initial_epsilon, "its dissipation rate, m^2/s^3", config::greater(0.0));
      finite_eddy_viscosity(s, initial_k, initial_epsilon);
    });
    v.section(
        "inlet", "k and epsilon of the fluid entering through velocity faces (Dirichlet)",
        [&](config::Visitor& s) {
          if (s.reading() && !inlet_given) return;
          s.required("k", inlet_k, "m^2/s^2", config::greater(0.0));
          s.required("epsilon", inlet_epsilon, "m^2/s^3", config::greater(0.0));
          finite_eddy_viscosity(s, inlet_k, inlet_epsilon);
        },
        &inlet_given);
  }
};

}  // namespace coflow::fluid
