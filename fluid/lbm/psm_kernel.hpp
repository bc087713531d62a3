// The collision of a partially saturated cell (Noble & Torczynski 1998; seed
// 000 eqs 2.66-2.68): one cell, no MPI, no allocation. With the streamed
// populations f of the cell, its solid fraction eps and the solid's velocity
// u_s (lattice units):
//   f_q <- f_q - (1 - B) omega (f_q - feq_q) + (1 - B) S_q + B Omega^s_q,
//   Omega^s_q = f_opp(q) - feq_opp(q)(rho, u) + feq_q(rho, u_s) - f_q,
// with B of eq. 2.67 and the Guo source S_q scaled by the fluid share 1 - B.
// (Eq. 2.68 as printed takes the solid equilibrium of opp(q); the original
// has feq_q(rho, u_s), which conserves momentum and is used here.)
#pragma once

#include "fluid/lbm/collision.hpp"
#include "fluid/lbm/colour_gradient.hpp"

namespace coflow::fluid::lbm {

// f: the cell's streamed populations (zero-centred); F: the body force
// density; out: the new populations; gain: += the fluid's momentum gain
// sum_q B Omega^s_q e_q.
template <class L, bool Incompressible>
inline void psm_collide(const double* f, const double* F, double omega, double tau, double eps, const double* us,
                        double* out, double* gain) {
  double rho = 0, jm[3] = {0, 0, 0};
  for (int q = 0; q < L::Q; ++q) {
    rho += f[q];
    for (int d = 0; d < 3; ++d) jm[d] += L::e[q][d] * f[q];
  }
  rho += 1.0;  // zero-centred populations (collision.hpp)
  const double rho_m = Incompressible ? 1.0 : rho;
  const double u[3] = {(jm[0] + 0.5 * F[0]) / rho_m, (jm[1] + 0.5 * F[1]) / rho_m, (jm[2] + 0.5 * F[2]) / rho_m};
  const double B = eps * (tau - 0.5) / ((1.0 - eps) + (tau - 0.5));  // eq. 2.67
  double feq[L::Q], feq_s[L::Q];
  for (int q = 0; q < L::Q; ++q) {
    feq[q] = equilibrium<L, Incompressible>(q, rho, u);
    feq_s[q] = equilibrium<L, Incompressible>(q, rho, us);
  }
  double g[3] = {0, 0, 0}, uF = 0;
  for (int d = 0; d < 3; ++d) uF += u[d] * F[d];
  for (int q = 0; q < L::Q; ++q) {
    const int o = L::opp[q];
    const double omega_s = f[o] - feq[o] + feq_s[q] - f[q];
    double eu = 0, eF = 0;
    for (int d = 0; d < 3; ++d) {
      eu += L::e[q][d] * u[d];
      eF += L::e[q][d] * F[d];
    }
    const double S = (1.0 - 0.5 * omega) * L::w[q] * (3.0 * (eF - uF) + 9.0 * eu * eF);
    out[q] = f[q] - (1.0 - B) * omega * (f[q] - feq[q]) + (1.0 - B) * S + B * omega_s;
    for (int d = 0; d < 3; ++d) g[d] += B * omega_s * L::e[q][d];
  }
  for (int d = 0; d < 3; ++d) gain[d] += g[d];
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
  return uu;
}

}  // namespace coflow::fluid::lbm
