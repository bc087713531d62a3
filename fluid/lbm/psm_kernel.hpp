// The collision of a partially saturated cell (Noble & Torczynski 1998; seed
// 000 eqs 2.66-2.68): one cell, no MPI, no allocation. With the streamed
// populations f of the cell, its solid fraction eps and the solid's velocity
// u_s (lattice units):
//   f_q <- f_q - (1 - B) omega (f_q - feq_q) + (1 - B) S_q + B Omega^s_q,
//   Omega^s_q = f_opp(q) - feq_opp(q)(rho, u) + feq_q(rho, u_s) - f_q,
// with B of eq. 2.67 and the Guo source S_q scaled by the fluid share 1 - B.
// With TRT (omega_minus != omega) the fluid share is the two-relaxation-time
// collision of collision.hpp's trt_pair: each pair's even part relaxes with
// omega, its odd part with omega_minus, the source split alike; B keeps the
// viscous tau (eq. 2.67), as the even part does.
// (Eq. 2.68 as printed takes the solid equilibrium of opp(q); the original
// has feq_q(rho, u_s), which conserves momentum and is used here.)
#pragma once

#include "fluid/lbm/collision.hpp"
#include "fluid/lbm/colour_gradient.hpp"

namespace coflow::fluid::lbm {

// f: the cell's streamed populations (zero-centred); F: the body force
// density; out: the new populations; gain: += the fluid's momentum gain
// sum_q B Omega^s_q e_q, less the body force's solid share B F: the body
// force stands for a pressure gradient (a driven flow's, or the hydrostatic
// one of the fluid's weight), which pushes the solid's volume as it pushes
// the fluid's; the fluid's source takes 1 - B of it, so the solid (which
// receives minus the gain) takes B F and the mixture F in every cell (the
// driven drag array's load balances f L^3; a grain in a closed box whose
// fluid weighs f = rho_f g feels Archimedes' buoyancy from the fluid's
// pressure less this share, to which immersed.psm.buoyancy's -rho_f V g is
// added). Directions go in pairs (q, opp(q)), e_opp = -e_q:
// each pair's equilibria share e.u and (e.u)^2 (collision.hpp's trt_pair
// folds the cell's terms the same way). One cell (T = double) or four
// neighbours along x (T = Vec4, each lane with its own fraction and solid
// velocity: the same arithmetic per lane). Returns u^2 of the cell (the
// Mach check's).
template <class L, bool Incompressible, class T>
[[gnu::always_inline]] inline T psm_collide_lanes(const T* f, const double* F, double omega,
                                                  double omega_minus, double tau, T eps, const T* us, T* out,
                                                  T* gain) {
  T dev = splat<T>(0.0),
    jm[3] = {dev, dev, dev};  // the density's deviation from 1 (zero-centred populations)
  // Unrolled, so that the lattice's vectors are constants, not converted ints.
#pragma GCC unroll 32
  for (int q = 0; q < L::Q; ++q) {
    dev += f[q];
    for (int d = 0; d < 3; ++d) jm[d] += L::e[q][d] * f[q];
  }
  const T rho_m = Incompressible ? splat<T>(1.0) : 1.0 + dev;
  const T u[3] = {(jm[0] + 0.5 * F[0]) / rho_m, (jm[1] + 0.5 * F[1]) / rho_m, (jm[2] + 0.5 * F[2]) / rho_m};
  const T B = eps * (tau - 0.5) / ((1.0 - eps) + (tau - 0.5));  // eq. 2.67
  const T uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2], ss = us[0] * us[0] + us[1] * us[1] + us[2] * us[2];
  const T uF = u[0] * F[0] + u[1] * F[1] + u[2] * F[2];
  // feq_q(u) = w_q (e0 + c45 (e.u)^2 + c3 e.u), and the solid's with e0s, u_s.
  const T e0 = dev - 1.5 * rho_m * uu, e0s = dev - 1.5 * rho_m * ss, c45 = 4.5 * rho_m, c3 = 3.0 * rho_m;
  const T fluid = (1.0 - B) * omega, share = 1.0 - B;
  const double source = 1.0 - 0.5 * omega, source_minus = 1.0 - 0.5 * omega_minus;
  // The rest population: Omega^s_0 = feq_0(u_s) - feq_0(u).
  out[0] = f[0] - fluid * (f[0] - L::w[0] * e0) + share * source * L::w[0] * (-3.0 * uF) +
           B * L::w[0] * (e0s - e0);
  T g[3] = {splat<T>(0.0), splat<T>(0.0), splat<T>(0.0)};
#pragma GCC unroll 32
  for (int q = 1; q < L::Q; ++q) {
    const int o = L::opp[q];
    if (o < q) continue;  // each pair once
    const double w = L::w[q];
    T eu = splat<T>(0.0), es = eu;
    double eF = 0;
    for (int d = 0; d < 3; ++d) {
      eu += L::e[q][d] * u[d];
      es += L::e[q][d] * us[d];
      eF += L::e[q][d] * F[d];
    }
    const T even = e0 + c45 * eu * eu, odd = c3 * eu, even_s = e0s + c45 * es * es, odd_s = c3 * es;
    const T feq_q = w * (even + odd), feq_o = w * (even - odd);
    const T fs_q = w * (even_s + odd_s), fs_o = w * (even_s - odd_s);
    const T os_q = f[o] - feq_o + fs_q - f[q], os_o = f[q] - feq_q + fs_o - f[o];
    const T s_even = 9.0 * eu * eF - 3.0 * uF;
    if (omega_minus == omega) {  // BGK
      const T s_q = source * w * (s_even + 3.0 * eF), s_o = source * w * (s_even - 3.0 * eF);
      out[q] = f[q] - fluid * (f[q] - feq_q) + share * s_q + B * os_q;
      out[o] = f[o] - fluid * (f[o] - feq_o) + share * s_o + B * os_o;
    } else {  // TRT: the fluid share's even and odd parts
      const T plus = 0.5 * (f[q] + f[o]) - w * even, minus = 0.5 * (f[q] - f[o]) - w * odd;
      const T ev = share * (omega * plus - source * w * s_even);
      const T od = share * (omega_minus * minus - source_minus * w * 3.0 * eF);
      out[q] = f[q] - ev - od + B * os_q;
      out[o] = f[o] - ev + od + B * os_o;
    }
    for (int d = 0; d < 3; ++d) g[d] += B * (os_q - os_o) * L::e[q][d];
  }
  // The solid takes the body force's share B of the cell, which the fluid's
  // source (scaled by 1 - B) leaves (the note above).
  for (int d = 0; d < 3; ++d) gain[d] += g[d] - B * F[d];
  return uu;
}

template <class L, bool Incompressible>
inline double psm_collide(const double* f, const double* F, double omega, double omega_minus, double tau,
                          double eps, const double* us, double* out, double* gain) {
  return psm_collide_lanes<L, Incompressible, double>(f, F, omega, omega_minus, tau, eps, us, out, gain);
}

// A partially saturated cell in two fluids (coflow's extension of eq. 2.66;
// the seed couples moving grains with one fluid only). r, b: the cell's
// streamed red and blue populations (whole, colour_gradient.hpp); g: its
// colour gradient; eps, us as above. The fluid share is the colour collision
// (perturbation and recolouring included), the solid share Noble &
// Torczynski's, split between the colours by the cell's red fraction
// psi = rho_r / rho:
//   r_q <- (1 - B) r*_q + B [r_opp(q) + psi (feq_q(rho, u_s) - feq_opp(q)(rho, u))]
// (blue with 1 - psi), r* the colour collision's result. The solid share sums
// to the cell's own colour mass (the two equilibria have the same density), so
// each colour keeps its mass; the sum of the colours is eq. 2.66 with the
// colour collision as the fluid's. Returns u^2 of the fluid share.
template <class L, bool Incompressible>
inline double psm_colour_collide(double* r, double* b, const double g[3], const ColourParams& p, const double* F,
                                 double eps, const double* us, double* gain) {
  double r0[L::Q], b0[L::Q], rho_r = 0.0, rho_b = 0.0, j[3] = {0.0, 0.0, 0.0};
  for (int q = 0; q < L::Q; ++q) {
    r0[q] = r[q], b0[q] = b[q];
    rho_r += r[q], rho_b += b[q];
    for (int d = 0; d < 3; ++d) j[d] += L::e[q][d] * (r[q] + b[q]);
  }
  const double rho = rho_r + rho_b, rho_m = Incompressible ? 1.0 : rho, psi = rho_r / rho;
  const double u[3] = {(j[0] + 0.5 * F[0]) / rho_m, (j[1] + 0.5 * F[1]) / rho_m, (j[2] + 0.5 * F[2]) / rho_m};
  const double tau = mixed_tau((rho_r - rho_b) / rho, p.tau_red, p.tau_blue);
  const double B = eps * (tau - 0.5) / ((1.0 - eps) + (tau - 0.5));  // eq. 2.67
  const double uu = colour_collide<L, Incompressible>(r, b, g, p, F);
  for (int q = 0; q < L::Q; ++q) {
    const int o = L::opp[q];
    const double swap = equilibrium<L, Incompressible>(q, rho, us) - equilibrium<L, Incompressible>(o, rho, u);
    const double omega_s = r0[o] + b0[o] - r0[q] - b0[q] + swap;  // eq. 2.68, Noble & Torczynski's form
    r[q] = (1.0 - B) * r[q] + B * (r0[o] + psi * swap);
    b[q] = (1.0 - B) * b[q] + B * (b0[o] + (1.0 - psi) * swap);
    for (int d = 0; d < 3; ++d) gain[d] += B * omega_s * L::e[q][d];
  }
  for (int d = 0; d < 3; ++d) gain[d] -= B * F[d];  // the body force's solid share, as above
  return uu;
}

}  // namespace coflow::fluid::lbm
