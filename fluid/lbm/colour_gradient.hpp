// The colour-gradient two-phase collision of one cell (seed 000 §2.3.4):
// collision of the total populations (eq. 2.54), interfacial perturbation
// (eq. 2.57), recolouring (Latva-Kokko & Rothman 2005, eqs. 2.59-2.63).
// Red and blue populations are stored whole (not zero-centred); the colour
// field is phi = rho_r - rho_b. No MPI, no allocation.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "fluid/lbm/collision.hpp"
#include "fluid/lbm/lattice.hpp"

namespace coflow::fluid::lbm {

// The colour field phi of a cell whose colours sum to r and b: r - b (seed 000
// eq. 2.56's difference) or, with `phase`, (r - b) / (r + b), which is
// constant in a region of one colour whatever its density.
inline double colour_field(double r, double b, bool phase) {
  return phase ? (r - b) / (r + b) : r - b;
}

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
// (docs/validation.md). On D2Q9 this is the seed's form with C = 3/5, not Reis
// & Phillips' (2007) B_i: the same anisotropic stress (so the same gamma), plus
// an isotropic part inside the interface, as the seed's D3Q19 form has.
// Written with omega = 1 / tau, per cell (T = double) or per lane (Vec4).
template <class L, class T>
inline T perturbation_amplitude(double gamma, T omega) {
  return gamma / (32.0 * positive_count<L>()) * omega;
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

// Red's part of a rebuilt population `total` whose old value was red r and
// blue b: total r / (r + b), exactly total where there is no blue (one fluid
// with solids runs as red alone, and (total r) / r can miss total by an ulp:
// blue of round-off, which the interpolated bounce-back let grow before it
// kept each colour's mass).
inline double share_red(double total, double r, double b) {
  return b == 0.0 ? total : total * r / (r + b);
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
// Per cell (T = double) or per lane (Vec4). psi is held to [-1, 1]: a colour
// whose density dips below zero (axis links against the gradient at beta
// near 1) would otherwise take the mean past either viscosity, and at a
// viscosity ratio M its denominator reaches zero at psi = -1 - 2 / (M - 1).
template <class T>
inline T mixed_tau(T psi, double tau_red, double tau_blue) {
  const double hr = 0.5 / (tau_red - 0.5), hb = 0.5 / (tau_blue - 0.5);
  if constexpr (std::is_same_v<T, double>) {
    psi = std::clamp(psi, -1.0, 1.0);
  } else {
    const T one = {1.0, 1.0, 1.0, 1.0};
    psi = psi > one ? one : psi;
    psi = psi < -one ? -one : psi;
  }
  return 0.5 + 1.0 / ((1.0 + psi) * hr + (1.0 - psi) * hb);
}

// A value of one cell (double) or of four (Vec4) with every lane x.
template <class T>
[[gnu::always_inline]] inline T splat(double x) {
  if constexpr (std::is_same_v<T, double>)
    return x;
  else
    return T{x, x, x, x};
}
[[gnu::always_inline]] inline double vsqrt(double x) { return std::sqrt(x); }
[[gnu::always_inline]] inline Vec4 vsqrt(Vec4 x) {
#if defined(__AVX__)
  return _mm256_sqrt_pd(x);
#else
  return Vec4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}

// The TRT (BGK: omega_minus = omega) collision with Guo forcing of zero-centred
// populations f, per lane with its own relaxation rates: collide()'s
// arithmetic on T. Returns u^2.
template <class L, bool Incompressible, class T>
[[gnu::always_inline]] inline T collide_lanes(T* f, T omega, T omega_minus, const double* F) {
  T rho = f[0], jx = splat<T>(0.0), jy = jx, jz = jx;  // rho: the deviation rho - 1
#pragma GCC unroll 32
  for (int q = 1; q < L::Q; ++q) {
    rho += f[q];
    jx += L::e[q][0] * f[q];
    jy += L::e[q][1] * f[q];
    jz += L::e[q][2] * f[q];
  }
  const T rho_m = Incompressible ? splat<T>(1.0) : 1.0 + rho;
  const T inv = Incompressible ? splat<T>(1.0) : 1.0 / rho_m;
  const T ux = (jx + 0.5 * F[0]) * inv, uy = (jy + 0.5 * F[1]) * inv, uz = (jz + 0.5 * F[2]) * inv;
  const T uu = ux * ux + uy * uy + uz * uz, uF = ux * F[0] + uy * F[1] + uz * F[2];
  const T e0 = rho - 1.5 * rho_m * uu, c45 = 4.5 * rho_m, c3 = 3.0 * rho_m;
  const T force_plus = 1.0 - 0.5 * omega, force_minus = 1.0 - 0.5 * omega_minus;
  T moving = splat<T>(0.0);
#pragma GCC unroll 32
  for (int q = 1; q < L::Q; ++q) {
    const int o = L::opp[q];
    if (o < q) continue;
    const T eu = L::e[q][0] * ux + L::e[q][1] * uy + L::e[q][2] * uz;
    const double eF = L::e[q][0] * F[0] + L::e[q][1] * F[1] + L::e[q][2] * F[2], w = L::w[q];
    const T plus = 0.5 * (f[q] + f[o]), minus = 0.5 * (f[q] - f[o]);
    const T s_plus = (force_plus * w) * (9.0 * eF * eu - 3.0 * uF), s_minus = force_minus * (w * 3.0 * eF);
    const T even = omega * (plus - w * (e0 + c45 * eu * eu)) - s_plus;
    const T odd = omega_minus * (minus - w * c3 * eu) - s_minus;
    f[q] = f[q] - even - odd;
    f[o] = f[o] - even + odd;
    moving += f[q] + f[o];
  }
  f[0] = rho - moving;
  return uu;
}

// The perturbation and recolouring of the collided total f (post-collision,
// not zero-centred) into red r and blue b (rest populations included), for
// colour_collide_lanes: g the colour gradient, omega the mixed rate, rho_r and
// rho_b the colours' pre-collision densities, inv_rho their sum's reciprocal.
template <class L, class T>
[[gnu::always_inline]] inline void recolour_lanes(T* f, T* r, T* b, const T g[3], const ColourParams& p,
                                                  T omega, T rho_r, T rho_b, T inv_rho) {
  const T zero = splat<T>(0.0), gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
  const auto some = gg > zero;  // lanes with a gradient; the others are only split
  const T gn = vsqrt(gg), inv_gg = some ? 1.0 / gg : zero;
  const T A = perturbation_amplitude<L>(p.gamma, omega);
  // Red's share, exactly 1 where there is no blue (one fluid with solids runs
  // as red alone: rho_r / rho_r by the reciprocal can miss 1 by an ulp and
  // make blue of round-off, which a boundary that does not keep each
  // colour's mass, as the interpolated bounce-back once did, lets grow).
  const T share = rho_b == zero ? splat<T>(1.0) : rho_r * inv_rho,
          recolour = some ? p.beta * rho_r * rho_b * inv_rho / gn : zero;
  T sr = zero, sb = zero;
#pragma GCC unroll 32
  for (int q = 1; q < L::Q; ++q) {
    const T eg = L::e[q][0] * g[0] + L::e[q][1] * g[1] + L::e[q][2] * g[2];
    f[q] += (36.0 * L::w[q]) * A * gn * (eg * eg * inv_gg - perturbation_shift<L>());  // eq. 2.57
    r[q] = share * f[q] + recolour * (L::w[q] * inverse_length<L>(q)) * eg;            // eqs. 2.59, 2.63
    b[q] = f[q] - r[q];                                                                // eq. 2.60
    sr += r[q], sb += b[q];
  }
  // The rest populations take what the moving ones leave of each colour, so
  // that each colour's mass is kept to round-off.
  r[0] = rho_r - sr;
  b[0] = rho_b - sb;
}

// One cell (T = double) or four (T = Vec4, the lanes independent, the same
// arithmetic, so that a cell gets the same bits either way): red r and blue b
// pulled (pre-collision); g the colour gradient of eq. 2.56; F the force
// density. Writes the post-collision, recoloured populations back into r and
// b. Returns u^2. Incompressible: the equilibrium of He & Luo (reference
// density 1 in the velocity terms). Blue false: red alone (red_collide_lanes
// below); b and g are not read.
template <class L, bool Incompressible, class T, bool Blue = true>
[[gnu::always_inline]] inline T colour_collide_lanes(T* r, T* b, const T g[3], const ColourParams& p,
                                                     const double* F) {
  T rho_r = r[0], rho_b = splat<T>(0.0), f[L::Q];
  if constexpr (Blue) rho_b = b[0];
#pragma GCC unroll 32
  for (int q = 1; q < L::Q; ++q) {
    rho_r += r[q];
    if constexpr (Blue) rho_b += b[q];
  }
#pragma GCC unroll 32
  for (int q = 0; q < L::Q; ++q) f[q] = (Blue ? r[q] + b[q] : r[q]) - L::w[q];  // zero-centred
  const T rho = rho_r + rho_b, inv_rho = 1.0 / rho, psi = (rho_r - rho_b) * inv_rho;
  const T tau = mixed_tau(psi, p.tau_red, p.tau_blue), omega = 1.0 / tau;
  const T omega_minus = p.trt ? 1.0 / (0.5 + p.magic / (tau - 0.5)) : omega;
  const T uu = collide_lanes<L, Incompressible>(f, omega, omega_minus, F);
#pragma GCC unroll 32
  for (int q = 0; q < L::Q; ++q) f[q] += L::w[q];
  if constexpr (Blue) {
    recolour_lanes<L>(f, r, b, g, p, omega, rho_r, rho_b, inv_rho);
  } else {  // red becomes the collided total, its rest population what the moving ones leave
    T sr = splat<T>(0.0);
#pragma GCC unroll 32
    for (int q = 1; q < L::Q; ++q) {
      r[q] = f[q];
      sr += r[q];
    }
    r[0] = rho_r - sr;
  }
  return uu;
}

// colour_collide_lanes where there is no blue (b = +0 in every population)
// and no surface tension (one fluid with interior solids): its perturbation
// and recolouring then add zeros, so red becomes the collided total and its
// rest population what the moving ones leave, blue stays +0, whatever the
// colour gradient. The same operations on red in the same order, so the same
// bits (rho_r + 0 and rho_r - 0 are rho_r); blue is not read or written.
template <class L, bool Incompressible, class T>
[[gnu::always_inline]] inline T red_collide_lanes(T* r, const ColourParams& p, const double* F) {
  return colour_collide_lanes<L, Incompressible, T, false>(r, nullptr, nullptr, p, F);
}

template <class L, bool Incompressible>
inline double colour_collide(double* r, double* b, const double g[3], const ColourParams& p, const double* F) {
  return colour_collide_lanes<L, Incompressible, double>(r, b, g, p, F);
}

}  // namespace coflow::fluid::lbm
