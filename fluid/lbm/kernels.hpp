// Lattice Boltzmann cell kernels: one cell, no MPI, no I/O, no allocation.
#pragma once

#include "fluid/lbm/lattice.hpp"

namespace coflow::fluid::lbm {

struct CollisionParams {
  double tau = 0.8;
  double omega = 1.25;        // 1 / tau
  double force_factor = 0.0;  // 1 - 1 / (2 tau), Guo forcing
};

inline CollisionParams collision_params(double tau) { return {tau, 1.0 / tau, 1.0 - 0.5 / tau}; }

// BGK collision with Guo forcing on the populations f of one cell, in place.
// Equilibrium: seed 000 eq. 2.33 (standard, rho_m = rho) or eq. 2.47 / c_s^2
// (He & Luo incompressible, rho_m = rho_0 = 1); collision eqs 2.42 / 2.45.
// F: force density (lattice units). Returns u^2 of the cell (for the Mach check).
template <class L, bool Incompressible>
inline double collide(double* f, const CollisionParams& p, const double* F) {
  double rho = 0.0, jx = 0.0, jy = 0.0, jz = 0.0;
  for (int q = 0; q < L::Q; ++q) {
    rho += f[q];
    jx += L::e[q][0] * f[q];
    jy += L::e[q][1] * f[q];
    jz += L::e[q][2] * f[q];
  }
  const double rho_m = Incompressible ? 1.0 : rho;
  const double inv = Incompressible ? 1.0 : 1.0 / rho_m;
  const double ux = (jx + 0.5 * F[0]) * inv, uy = (jy + 0.5 * F[1]) * inv, uz = (jz + 0.5 * F[2]) * inv;
  const double uu = ux * ux + uy * uy + uz * uz;
  const double uF = ux * F[0] + uy * F[1] + uz * F[2];
  // Collision conserves mass exactly; the rest population (q = 0) takes what
  // the others leave, so that rounding cannot bias the total mass.
  double moving = 0.0;
  for (int q = 1; q < L::Q; ++q) {
    const double eu = L::e[q][0] * ux + L::e[q][1] * uy + L::e[q][2] * uz;
    const double eF = L::e[q][0] * F[0] + L::e[q][1] * F[1] + L::e[q][2] * F[2];
    const double feq = L::w[q] * (rho + rho_m * (3.0 * eu + 4.5 * eu * eu - 1.5 * uu));
    const double source = p.force_factor * L::w[q] * (3.0 * (eF - uF) + 9.0 * eu * eF);
    f[q] = f[q] - (f[q] - feq) * p.omega + source;
    moving += f[q];
  }
  f[0] = rho - moving;
  return uu;
}

// The same collision for W cells at once, cell index innermost so that every
// operation is a vector operation (same arithmetic, same order as collide()).
// The loops over q are unrolled so that the lattice vectors are constants and
// the zero and unit components cost nothing.
template <class L, bool Incompressible, int W>
inline void collide_chunk(double (&f)[L::Q][W], const CollisionParams& p, const double* F, double* u2) {
  double rho[W], ux[W], uy[W], uz[W], uu[W], uF[W], moving[W];
  for (int w = 0; w < W; ++w) rho[w] = ux[w] = uy[w] = uz[w] = 0.0;
#pragma GCC unroll 19
  for (int q = 0; q < L::Q; ++q)
    for (int w = 0; w < W; ++w) {
      rho[w] += f[q][w];
      ux[w] += L::e[q][0] * f[q][w];
      uy[w] += L::e[q][1] * f[q][w];
      uz[w] += L::e[q][2] * f[q][w];
    }
  for (int w = 0; w < W; ++w) {
    const double inv = Incompressible ? 1.0 : 1.0 / rho[w];
    ux[w] = (ux[w] + 0.5 * F[0]) * inv;
    uy[w] = (uy[w] + 0.5 * F[1]) * inv;
    uz[w] = (uz[w] + 0.5 * F[2]) * inv;
    uu[w] = ux[w] * ux[w] + uy[w] * uy[w] + uz[w] * uz[w];
    uF[w] = ux[w] * F[0] + uy[w] * F[1] + uz[w] * F[2];
    moving[w] = 0.0;
    u2[w] = uu[w];
  }
#pragma GCC unroll 19
  for (int q = 1; q < L::Q; ++q) {
    const double eF = L::e[q][0] * F[0] + L::e[q][1] * F[1] + L::e[q][2] * F[2];
    for (int w = 0; w < W; ++w) {
      const double rho_m = Incompressible ? 1.0 : rho[w];
      const double eu = L::e[q][0] * ux[w] + L::e[q][1] * uy[w] + L::e[q][2] * uz[w];
      const double feq = L::w[q] * (rho[w] + rho_m * (3.0 * eu + 4.5 * eu * eu - 1.5 * uu[w]));
      const double source = p.force_factor * L::w[q] * (3.0 * (eF - uF[w]) + 9.0 * eu * eF);
      f[q][w] = f[q][w] - (f[q][w] - feq) * p.omega + source;
      moving[w] += f[q][w];
    }
  }
  for (int w = 0; w < W; ++w) f[0][w] = rho[w] - moving[w];
}

template <class L, bool Incompressible>
inline double equilibrium(int q, double rho, const double* u) {
  const double eu = L::e[q][0] * u[0] + L::e[q][1] * u[1] + L::e[q][2] * u[2];
  const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  const double rho_m = Incompressible ? 1.0 : rho;
  return L::w[q] * (rho + rho_m * (3.0 * eu + 4.5 * eu * eu - 1.5 * uu));
}

// Zou & He (1997) closure of the unknown populations at a node of a face with
// inward normal s along `axis`, general form of Hecht & Harting (2010):
//   f_q = f_opp(q) + 6 w_q rho_m (e_q . u) - sum_t e_q,t N_t,
//   N_t = 1/2 sum_{e_q,axis = 0} f_q e_q,t - rho_m u_t / 3.
// velocity face: u given (all components), rho from mass balance;
// pressure face: rho given, u normal from mass balance, tangential u = 0.
template <class L, bool Incompressible>
inline void zou_he(double* f, int axis, int s, bool velocity_face, double rho_given, const double* u_given) {
  double s0 = 0.0, sout = 0.0;
  for (int q = 0; q < L::Q; ++q) {
    if (L::e[q][axis] == 0) s0 += f[q];
    if (s * L::e[q][axis] < 0) sout += f[q];
  }
  double rho, u[3] = {0.0, 0.0, 0.0};
  if (velocity_face) {
    for (int d = 0; d < 3; ++d) u[d] = u_given[d];
    const double un = s * u[axis];
    rho = Incompressible ? s0 + 2.0 * sout + un : (s0 + 2.0 * sout) / (1.0 - un);
  } else {
    rho = rho_given;
    const double un = Incompressible ? rho - s0 - 2.0 * sout : 1.0 - (s0 + 2.0 * sout) / rho;
    u[axis] = s * un;
  }
  const double rho_m = Incompressible ? 1.0 : rho;
  double N[3] = {0.0, 0.0, 0.0};
  for (int t = 0; t < 3; ++t) {
    if (t == axis) continue;
    for (int q = 0; q < L::Q; ++q)
      if (L::e[q][axis] == 0) N[t] += 0.5 * f[q] * L::e[q][t];
    N[t] -= rho_m * u[t] / 3.0;
  }
  for (int q = 0; q < L::Q; ++q) {
    if (s * L::e[q][axis] <= 0) continue;
    const double eu = L::e[q][0] * u[0] + L::e[q][1] * u[1] + L::e[q][2] * u[2];
    double v = f[L::opp[q]] + 6.0 * L::w[q] * rho_m * eu;
    for (int t = 0; t < 3; ++t)
      if (t != axis) v -= L::e[q][t] * N[t];
    f[q] = v;
  }
}

}  // namespace coflow::fluid::lbm
