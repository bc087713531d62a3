// The colour-gradient two-phase collision of one cell (seed 000 §2.3.4):
// collision of the total populations (eq. 2.54), interfacial perturbation
// (eq. 2.57), recolouring (Latva-Kokko & Rothman 2005, eqs. 2.59-2.63).
// Red and blue populations are stored whole (not zero-centred); the colour
// field is phi = rho_r - rho_b. No MPI, no allocation.
#pragma once

#include <algorithm>
#include <cmath>

#include "fluid/lbm/collision.hpp"
#include "fluid/lbm/lattice.hpp"

namespace coflow::fluid::lbm {

// The lattice's number of velocities with e_x = +1 (5 for D3Q19, 3 for D2Q9):
// the colour gradient of eq. 2.56, g = sum_q e_q phi(x + e_q) without weights,
// is 2 N dphi/dx to first order.
template <class L>
constexpr int positive_count() {
  int n = 0;
  for (int q = 0; q < L::Q; ++q) n += L::e[q][0] == 1 ? 1 : 0;
  return n;
}

// The constant of eq. 2.57 that makes the perturbation conserve mass when it
// acts on the moving populations only: sum_{q>0} w_q (e_q.n)^2 = c_s^2 =
// C sum_{q>0} w_q, so C = c_s^2 / (1 - w_0): 1/2 for D3Q19 (the seed's value),
// 3/5 for D2Q9.
template <class L>
constexpr double perturbation_shift() {
  return cs2 / (1.0 - L::w[0]);
}

// The amplitude A of eq. 2.57 for a surface tension gamma (lattice units,
// reference density 1) where the relaxation time is tau. Derivation (the
// mechanical definition, eq. 2.55): at a flat interface with normal z the
// perturbation adds 36 w_q A |g| [(e_q.n)^2 - C] to the populations each step;
// the non-equilibrium part it feeds relaxes by (1 - 1/tau) per step, so the
// momentum flux carries tau times it, and p_N - p_T = tau 36 A |g|
// (sum w e_z^4 - sum w e_x^2 e_z^2) = tau 36 A |g| (1/3 - 1/9) = 8 tau A |g|
// (both lattices are isotropic to fourth order). The unweighted gradient's
// magnitude sums across the interface to 2 N (phi_red - phi_blue) = 4 N. So
// gamma = 32 N A tau: A = gamma / (160 tau) on D3Q19 (the seed's eq. 2.58
// writes 172), gamma / (96 tau) on D2Q9. The Laplace tests check it
// (docs/validation.md).
template <class L>
inline double perturbation_amplitude(double gamma, double tau) {
  return gamma / (32.0 * positive_count<L>() * tau);
}

// The colour gradient at a fluid cell x next to solids, from its fluid
// neighbours alone: per axis the weighted difference sum_q w_q e_qd (phi(x +
// e_q) - phi(x)) over the fluid links, divided by their sum_q w_q e_qd^2 and
// scaled by 2 N, so that in the bulk it equals eq. 2.56's unweighted sum
// (2 N dphi/dx); one-sided across the wall, with no value made up inside the
// solid.
template <class L, class Solid>
inline void fluid_gradient(const double* phi, const Solid* solid, const long* off, long x, double g[3]) {
  double num[3] = {0.0, 0.0, 0.0}, den[3] = {0.0, 0.0, 0.0};
  for (int q = 1; q < L::Q; ++q) {
    if (solid[x + off[q]]) continue;
    const double dphi = phi[x + off[q]] - phi[x];
    for (int d = 0; d < 3; ++d) {
      num[d] += L::w[q] * L::e[q][d] * dphi;
      den[d] += L::w[q] * L::e[q][d] * L::e[q][d];
    }
  }
  for (int d = 0; d < 3; ++d) g[d] = den[d] > 0.0 ? 2.0 * positive_count<L>() * num[d] / den[d] : 0.0;
}

// The same next to grains (partially saturated cells): each neighbour counts
// by its fluid share 1 - eps (eps = 1 in solid cells), so that a cell half
// covered by a grain weighs half in the one-sided gradient.
template <class L, class Eps>
inline void shared_gradient(const double* phi, Eps&& eps_at, const long* off, long x, double g[3]) {
  double num[3] = {0.0, 0.0, 0.0}, den[3] = {0.0, 0.0, 0.0};
  for (int q = 1; q < L::Q; ++q) {
    const double share = 1.0 - eps_at(x + off[q]);
    if (share <= 0.0) continue;
    const double dphi = phi[x + off[q]] - phi[x];
    for (int d = 0; d < 3; ++d) {
      num[d] += share * L::w[q] * L::e[q][d] * dphi;
      den[d] += share * L::w[q] * L::e[q][d] * L::e[q][d];
    }
  }
  for (int d = 0; d < 3; ++d) g[d] = den[d] > 0.0 ? 2.0 * positive_count<L>() * num[d] / den[d] : 0.0;
}

// Geometric wetting (Leclaire, Parmigiani, Malaspinas, Chopard & Latt 2017,
// Phys. Rev. E 95 033306, §II.E; Akai, Bijeljic
// & Blunt 2018): at a fluid cell next to solids the colour gradient g keeps its
// magnitude and its tangential direction t along the solid, and turns in the
// plane of (n_s, t) until the red fluid meets the solid at the contact angle:
// n' = -cos(theta) n_s + sin(theta) t, n_s the solid's unit normal into the
// fluid (the drop's outward normal -n' then makes theta with n_s). A gradient
// along n_s alone has no tangential direction and is left as it is.
inline void wet_gradient(double g[3], const double ns[3], double cos_theta) {
  const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  // No gradient, or solids on opposite sides (a one-cell gap: no normal).
  if (gn == 0.0 || (ns[0] == 0.0 && ns[1] == 0.0 && ns[2] == 0.0)) return;
  const double c = (g[0] * ns[0] + g[1] * ns[1] + g[2] * ns[2]) / gn;
  double t[3];
  for (int d = 0; d < 3; ++d) t[d] = g[d] / gn - c * ns[d];
  const double tl = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
  if (tl < 1e-12) return;
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  for (int d = 0; d < 3; ++d) g[d] = gn * (-cos_theta * ns[d] + sin_theta * t[d] / tl);
}

// 1 / |e_q| (1 or 1/sqrt(2) on these lattices; 0 for the rest population).
template <class L>
constexpr double inverse_length(int q) {
  const int e2 = L::e[q][0] * L::e[q][0] + L::e[q][1] * L::e[q][1] + L::e[q][2] * L::e[q][2];
  return e2 == 0 ? 0.0 : e2 == 1 ? 1.0 : 0.70710678118654752440;
}

// The two fluids' parameters, lattice units.
struct ColourParams {
  double gamma = 0.0;  // surface tension
  double beta = 0.7;   // recolouring
  double tau_red = 0.8, tau_blue = 0.8;
  bool trt = false;
  double magic = 0.1875;
};

// The relaxation time at colour fraction psi = (rho_r - rho_b) / rho: the
// viscosities interpolated harmonically, 1/nu = (1 + psi)/(2 nu_r) +
// (1 - psi)/(2 nu_b) (Leclaire et al. 2017 eq. 13; it keeps the stress
// continuous across a layered interface), nu = (tau - 1/2)/3.
inline double mixed_tau(double psi, double tau_red, double tau_blue) {
  const double nr = tau_red - 0.5, nb = tau_blue - 0.5;
  return 0.5 + 1.0 / ((1.0 + psi) / (2.0 * nr) + (1.0 - psi) / (2.0 * nb));
}

// One cell: red r and blue b pulled (pre-collision); g the colour gradient of
// eq. 2.56; F the force density. Writes the post-collision, recoloured
// populations back into r and b. Returns u^2. Incompressible: the equilibrium
// of He & Luo (reference density 1 in the velocity terms).
template <class L, bool Incompressible>
inline double colour_collide(double* r, double* b, const double g[3], const ColourParams& p,
                             const double* F) {
  double rho_r = 0.0, rho_b = 0.0, f[L::Q];
  for (int q = 0; q < L::Q; ++q) {
    rho_r += r[q];
    rho_b += b[q];
    f[q] = r[q] + b[q] - L::w[q];  // zero-centred for lbm::collide
  }
  const double rho = rho_r + rho_b;
  const double tau = mixed_tau((rho_r - rho_b) / rho, p.tau_red, p.tau_blue);
  const double uu = collide<L, Incompressible>(f, collision_params(tau, p.trt, p.magic), F);
  for (int q = 0; q < L::Q; ++q) f[q] += L::w[q];
  const double gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
  if (gg > 0.0) {
    const double gn = std::sqrt(gg), inv_gg = 1.0 / gg, A = perturbation_amplitude<L>(p.gamma, tau);
    const double share = rho_r / rho, recolour = p.beta * rho_r * rho_b / (rho * gn);
    for (int q = 1; q < L::Q; ++q) {
      const double eg = L::e[q][0] * g[0] + L::e[q][1] * g[1] + L::e[q][2] * g[2];
      f[q] += 36.0 * L::w[q] * A * gn * (eg * eg * inv_gg - perturbation_shift<L>());  // eq. 2.57
      r[q] = share * f[q] + recolour * L::w[q] * eg * inverse_length<L>(q);            // eqs. 2.59, 2.63
      b[q] = f[q] - r[q];                                                              // eq. 2.60
    }
  } else {
    for (int q = 1; q < L::Q; ++q) {
      r[q] = rho_r / rho * f[q];
      b[q] = f[q] - r[q];
    }
  }
  // The rest populations take what the moving ones leave of each colour, so
  // that each colour's mass is kept to round-off (the perturbation and the
  // recolouring conserve it exactly in exact arithmetic).
  double sr = 0.0, sb = 0.0;
  for (int q = 1; q < L::Q; ++q) sr += r[q], sb += b[q];
  r[0] = rho_r - sr;
  b[0] = rho_b - sb;
  return uu;
}

}  // namespace coflow::fluid::lbm
