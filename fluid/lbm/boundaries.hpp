// Lattice Boltzmann boundaries of a block's faces: half-way bounce-back at
// walls (seed 000 eq. 2.44), the Zou-He closure of the unknown populations at
// pressure and velocity faces (Zou & He 1997; Hecht & Harting 2010), the
// regularized closure (Latt et al. 2008) and zero-gradient outflow. One cell or
// one face at a time, on the populations of a Layout; no MPI.
#pragma once

#include <array>

#include "fluid/lbm/collision.hpp"
#include "fluid/lbm/layout.hpp"
#include "fluid/lbm/setup.hpp"
#include "fluid/lbm/wall_tally.hpp"

namespace coflow::fluid::lbm {

// The density and velocity of a node on a face with inward normal s along
// `axis`, from its known populations (zero-centred) and the face's value
// (Zou & He 1997): a velocity face gives u, rho follows from mass balance; a
// pressure face gives rho, the normal u follows, the tangential u is zero.
// With Guo's forcing the populations' momentum is rho_m u - F/2 (F: the
// node's force density), so the mass balance takes the normal one, s (rho_m
// u_n) - s F_axis / 2, in place of rho_m u_n.
template <class L, bool Incompressible>
inline void face_state(const double* f, int axis, int s, bool velocity_face, double rho_given,
                       const double* u_given, const double* F, double& rho, double* u) {
  double s0 = 0.0, sout = 0.0;
  for (int q = 0; q < L::Q; ++q) {
    if (L::e[q][axis] == 0) s0 += f[q];
    if (s * L::e[q][axis] < 0) sout += f[q];
  }
  // s0 + 2 sout of the full populations: the weights add 1 (zero-centred
  // storage); less the force's half-step share of the normal momentum
  const double known = (s0 + 2.0 * sout) + 1.0 - 0.5 * s * F[axis];
  u[0] = u[1] = u[2] = 0.0;
  if (velocity_face) {
    for (int d = 0; d < 3; ++d) u[d] = u_given[d];
    const double un = s * u[axis];
    rho = Incompressible ? known + un : known / (1.0 - un);
  } else {
    rho = rho_given;
    const double un = Incompressible ? rho - known : 1.0 - known / rho;
    u[axis] = s * un;
  }
}

// Zou & He (1997) closure of the unknown populations at a node of a face with
// inward normal s along `axis`, general form of Hecht & Harting (2010):
//   f_q = f_opp(q) + 6 w_q (e_q . j) - sum_t e_q,t N_t,
//   N_t = 1/2 sum_{e_q,axis = 0} f_q e_q,t - j_t / 3,
// with j = rho_m u - F/2, the momentum the populations hold under Guo's
// forcing (rho_m u without a force).
template <class L, bool Incompressible>
inline void zou_he(double* f, int axis, int s, bool velocity_face, double rho_given, const double* u_given,
                   const double* F) {
  double rho, u[3];
  face_state<L, Incompressible>(f, axis, s, velocity_face, rho_given, u_given, F, rho, u);
  const double rho_m = Incompressible ? 1.0 : rho;
  const double j[3] = {rho_m * u[0] - 0.5 * F[0], rho_m * u[1] - 0.5 * F[1], rho_m * u[2] - 0.5 * F[2]};
  double N[3] = {0.0, 0.0, 0.0};
  for (int t = 0; t < 3; ++t) {
    if (t == axis) continue;
    for (int q = 0; q < L::Q; ++q)
      if (L::e[q][axis] == 0) N[t] += 0.5 * f[q] * L::e[q][t];
    N[t] -= j[t] / 3.0;
  }
  for (int q = 0; q < L::Q; ++q) {
    if (s * L::e[q][axis] <= 0) continue;
    const double ej = L::e[q][0] * j[0] + L::e[q][1] * j[1] + L::e[q][2] * j[2];
    double v = f[L::opp[q]] + 6.0 * L::w[q] * ej;
    for (int t = 0; t < 3; ++t)
      if (t != axis) v -= L::e[q][t] * N[t];
    f[q] = v;
  }
}

// f = f^eq + w / (2 c_s^4) (e e - c_s^2 I) : Pi, the regularized
// reconstruction (Latt et al. 2008) from an equilibrium and a stress.
template <class L>
inline void reconstruct(double* f, const double* feq, const double (&pi)[3][3]) {
  for (int q = 0; q < L::Q; ++q) {
    double qpi = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) qpi += (L::e[q][a] * L::e[q][b] - (a == b ? 1.0 / 3.0 : 0.0)) * pi[a][b];
    f[q] = feq[q] + 4.5 * L::w[q] * qpi;  // 1 / (2 c_s^4) = 9 / 2
  }
}

// Regularized closure (Latt, Chopard, Malaspinas, Deville & Michler 2008, Phys.
// Rev. E 77, 056703, §III.B): rho and u as Zou-He; the unknown populations'
// non-equilibrium parts by bounce-back of the opposite ones' (f_q^neq =
// f_opp(q)^neq); then every population of the node is rebuilt as
//   f_q = f_q^eq + w_q / (2 c_s^4) Q_q : Pi^neq,  Q_q = e_q e_q - c_s^2 I,
// with Pi^neq = sum_q e_q e_q f_q^neq, so that only the hydrodynamic part of
// the non-equilibrium survives (no odd-even mode at pressure faces).
//
// At a pressure face the velocity is the mean of the node's mass-balance value
// (Zou & He) and the next node's inwards (u_inner): for a smooth flow their
// normal components agree (to O(dx du/dx), zero in fully developed flow),
// while a two-cell (odd-even) mode along the flow has opposite signs in them.
// The tangential components, which Zou & He and Latt et al. set to zero, are
// then half the next node's: between that zero and a zero-gradient outlet
// (a flow leaving at an angle keeps half its tangential velocity at the face). Alone, the
// mass-balance velocity lets such a mode live in steady state, pinned at the
// face (+-7 % at Ma 0.09, tau 0.8: docs/validation.md); the mean gives it no
// amplitude there (3e-4).
//
// With a force density F the equilibrium here takes Guo's first-order term
// -3 w_q (e_q . F) / 2 (1 / (2 c_s^2) = 3 / 2): the rebuilt populations then
// hold the momentum rho_m u - F/2 the forcing's collision expects (rho_m u
// without it), and the known populations' non-equilibrium parts carry no
// first-order share of F that the bounce-back of the unknowns' would turn
// into a spurious Pi^neq.
template <class L, bool Incompressible>
inline void regularized(double* f, int axis, int s, bool velocity_face, double rho_given,
                        const double* u_given, const double* u_inner, const double* F) {
  double rho, u[3];
  face_state<L, Incompressible>(f, axis, s, velocity_face, rho_given, u_given, F, rho, u);
  if (!velocity_face)
    for (int d = 0; d < 3; ++d) u[d] = 0.5 * (u[d] + u_inner[d]);
  double feq[L::Q], neq[L::Q];
  for (int q = 0; q < L::Q; ++q)
    feq[q] = equilibrium<L, Incompressible>(q, rho, u) -
             1.5 * L::w[q] * (L::e[q][0] * F[0] + L::e[q][1] * F[1] + L::e[q][2] * F[2]);
  for (int q = 0; q < L::Q; ++q) {
    const int k = s * L::e[q][axis] > 0 ? L::opp[q] : q;  // unknown: its opposite's
    neq[q] = f[k] - feq[k];
  }
  double pi[3][3] = {};
  for (int q = 0; q < L::Q; ++q)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) pi[a][b] += L::e[q][a] * L::e[q][b] * neq[q];
  reconstruct<L>(f, feq, pi);
}

// The velocity of a node from its post-collision populations g (zero-centred,
// stride apart) of the last step and the force density F: Guo's forcing
// leaves the momentum rho u + F/2 after collision.
template <class L, bool Incompressible>
inline void post_collision_velocity(const double* g, long stride, const double* F, double* u) {
  double rho = 1.0, m[3] = {0.0, 0.0, 0.0};
  for (int q = 0; q < L::Q; ++q) {
    const double v = g[q * stride];
    rho += v;
    for (int d = 0; d < 3; ++d) m[d] += L::e[q][d] * v;
  }
  const double rho_m = Incompressible ? 1.0 : rho;
  for (int d = 0; d < 3; ++d) u[d] = (m[d] - 0.5 * F[d]) / rho_m;
}

// A node where two or three pressure or velocity faces meet (an edge or a
// corner of the box). No face's closure applies there: each face's unknowns
// include populations that only the other face could set, and some links
// are buried (both a population and its opposite unknown). The node is
// rebuilt whole instead, through the regularized closure's reconstruction
// (Latt et al. 2008): f = f^eq(rho, u) + w / (2 c_s^4) Q : Pi, with
// - u the first velocity face's value in face order, else the velocity of
//   the next node inwards along the diagonal (its last step's populations);
//   rho the first pressure face's value, else that node's density;
// - Pi's components between the meeting faces' normal axes, where the buried
//   links would enter, the first-order (Chapman-Enskog) stress -rho_m c_s^2
//   tau (du_b/dx_a + du_a/dx_b) with the derivatives one-sided into the box
//   (Skordos 1993, Phys. Rev. E 48, 4823: the stress from finite differences
//   of the velocity), from the node's u and the last step's velocity of the
//   next node inwards along each normal (inside the block: validate keeps
//   such blocks two cells thick);
// - its components along an axis that no meeting face is normal to (3D
//   edges) the regularized face closure's: the known populations'
//   non-equilibrium parts, an unknown one's from its opposite.
// Everything it reads lies in the node's block, so N ranks give 1 rank's bits.
// The unknown populations of a corner node: those entering through a face
// that meets there (meets[face]).
template <class L>
inline bool corner_unknown(const bool* meets, int q) {
  for (int face = 0; face < 6; ++face)
    if (meets[face] && (face % 2 == 0 ? 1 : -1) * L::e[q][face / 2] > 0) return true;
  return false;
}

// The rebuild itself, for any storage: f the node's zero-centred populations
// (the known ones as pulled), g its global indices, meets[face] the faces
// that meet there; state(d, u) gives the full density and the velocity of the
// node at offset d from this one (its last step's populations, d towards the
// box along the normals only).
template <class L, bool Incompressible, class State>
inline void rebuild_corner(double* f, const long g[3], const bool* meets, const std::array<Face, 6>& faces,
                           const double* F, double tau, State state) {
  bool normal[3] = {false, false, false};
  long in[3] = {0, 0, 0};
  for (int face = 0; face < 6; ++face)
    if (meets[face]) normal[face / 2] = true, in[face / 2] = face % 2 == 0 ? 1 : -1;
  double u[3];
  double rho = state(in, u);
  for (int face = 5; face >= 0; --face)  // the first in face order wins
    if (meets[face] && faces[face].type == FaceType::velocity) faces[face].velocity(g, face / 2, u);
  for (int face = 5; face >= 0; --face)
    if (meets[face] && faces[face].type == FaceType::pressure) rho = faces[face].rho;
  double feq[L::Q], pi[3][3] = {};
  for (int q = 0; q < L::Q; ++q)
    feq[q] = equilibrium<L, Incompressible>(q, rho, u) -
             1.5 * L::w[q] * (L::e[q][0] * F[0] + L::e[q][1] * F[1] + L::e[q][2] * F[2]);
  for (int q = 0; q < L::Q; ++q) {  // the known populations' estimate
    const int k = corner_unknown<L>(meets, q) ? L::opp[q] : q;
    const double neq = corner_unknown<L>(meets, k) ? 0.0 : f[k] - feq[k];  // buried: between normal axes only
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) pi[a][b] += L::e[q][a] * L::e[q][b] * neq;
  }
  double du[3][3] = {};  // du[a][b] = d u_b / d x_a along the normal axes
  for (int a = 0; a < 3; ++a) {
    if (!normal[a]) continue;
    long d[3] = {0, 0, 0};
    d[a] = in[a];
    double un[3];
    state(d, un);
    for (int b = 0; b < 3; ++b) du[a][b] = (un[b] - u[b]) * static_cast<double>(in[a]);
  }
  const double rho_m = Incompressible ? 1.0 : rho;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (normal[a] && normal[b]) pi[a][b] = -rho_m * tau / 3.0 * (du[a][b] + du[b][a]);
  reconstruct<L>(f, feq, pi);
}

// lbm's single-fluid storage: cur the last step's zero-centred populations
// of the block laid out by lay, loc the node's indices in the block.
template <class L, bool Incompressible>
inline void close_corner(double* f, const double* cur, const Layout& lay, const long loc[3],
                         const std::array<Face, 6>& faces, const bool* open, const double* F, double tau) {
  const long g[3] = {lay.origin[0] + loc[0], lay.origin[1] + loc[1], lay.origin[2] + loc[2]};
  bool meets[6];
  for (int face = 0; face < 6; ++face)
    meets[face] = open[face] && faces[face].type != FaceType::outflow &&
                  loc[face / 2] == (face % 2 == 0 ? 0 : lay.extent[face / 2] - 1);
  rebuild_corner<L, Incompressible>(f, g, meets, faces, F, tau, [&](const long d[3], double* u) {
    const long x = lay.idx(loc[0] + d[0], loc[1] + d[1], loc[2] + d[2]);
    post_collision_velocity<L, Incompressible>(&cur[x], lay.stride, F, u);
    double rho = 1.0;
    for (int q = 0; q < L::Q; ++q) rho += cur[q * lay.stride + x];
    return rho;
  });
}

// Half-way bounce-back (seed 000 eq. 2.44) on the wall faces [face0, face1)
// of a block: the population a boundary node pulls from beyond a wall is the
// one it sent towards the wall, reversed. f: the current populations (the
// ghosts beyond the walls are written); off: streaming offsets in cells.
// momentum (per cell and face, wall_tally.hpp): += the momentum each wall takes, 2 e_o g_o per
// population g_o bounced (Ladd's momentum exchange), relative to the fluid at
// rest (zero-centred populations: the reference pressure's share is left out).
// A population bounced at an edge of two walls counts for the first face; one
// that is unknown to an open face at the node (s e_q > 0 for that face; open:
// this block's faces that are pressure, velocity or outflow faces of the
// domain), whose value the face's condition sets, counts for none: the wall
// gave the node nothing. (A regularized face rebuilds the known populations
// too, but from their non-equilibrium stress: those stay the wall's.)
template <class L>
inline void fill_walls(double* f, const Layout& lay, const long* off, const bool* wall, const bool* open,
                       int face0, int face1, WallTally& momentum) {
  for (int face = face0; face < face1; ++face) {
    if (!wall[face]) continue;
    const int axis = face / 2, s = face % 2 == 0 ? 1 : -1;
    long lo[3] = {0, 0, 0}, hi[3] = {lay.extent[0], lay.extent[1], lay.extent[2]};
    lo[axis] = face % 2 == 0 ? 0 : lay.extent[axis] - 1;
    hi[axis] = lo[axis] + 1;
    for (long k = lo[2]; k < hi[2]; ++k)
      for (long j = lo[1]; j < hi[1]; ++j)
        for (long i = lo[0]; i < hi[0]; ++i) {
          const long x = lay.idx(i, j, k);
          const long at[3] = {i, j, k};
          double* m = momentum.at((k * lay.extent[1] + j) * lay.extent[0] + i, face);
          for (int q = 0; q < L::Q; ++q) {
            if (s * L::e[q][axis] <= 0) continue;
            const double g = f[L::opp[q] * lay.stride + x];
            f[q * lay.stride + x - off[q]] = g;
            bool first = true;  // no wall face before this one bounces the same population
            for (int other = 0; other < face && first; ++other) {
              const int a = other / 2, so = other % 2 == 0 ? 1 : -1;
              first = !(wall[other] && so * L::e[q][a] > 0 && at[a] == (other % 2 == 0 ? 0 : lay.extent[a] - 1));
            }
            bool kept = true;  // no open face's closure overwrites it at this node
            for (int other = 0; other < 6 && kept; ++other) {
              const int a = other / 2, so = other % 2 == 0 ? 1 : -1;
              kept =
                  !(open[other] && so * L::e[q][a] > 0 && at[a] == (other % 2 == 0 ? 0 : lay.extent[a] - 1));
            }
            if (first && kept)
              for (int d = 0; d < 3; ++d) m[d] += 2.0 * L::e[L::opp[q]][d] * g;
          }
        }
  }
}

// The unknown populations of the pulled cell f at (i, j, k) on the open faces
// of the block (open[face]): outflow faces first (zero gradient: the next
// node's post-collision populations of cur), then the Zou-He or regularized
// faces, in face order, as lbm-reference does. F: the cell's force density
// (it stands for the inner node's, which may lie in a halo). Always inlined:
// the compiler then contracts the closures' arithmetic into fused
// multiply-adds in the caller's context, as it did before this function was
// split out of the solver (compare_builds: the same bits).
template <class L, bool Incompressible>
[[gnu::always_inline]] inline void close_open_faces(double* f, const double* cur, const Layout& lay, long i,
                                                    long j, long k, const bool* open,
                                                    const std::array<Face, 6>& faces, const double* F,
                                                    double tau) {
  const long loc[3] = {i, j, k};
  const long x = lay.idx(i, j, k);
  int meeting = 0;  // pressure and velocity faces at this node
  for (int face = 0; face < 6; ++face)
    meeting += open[face] && faces[face].type != FaceType::outflow &&
               loc[face / 2] == (face % 2 == 0 ? 0 : lay.extent[face / 2] - 1);
  for (int pass = 0; pass < 2; ++pass)
    for (int face = 0; face < 6; ++face) {
      if (pass == 1 && meeting > 1) {
        close_corner<L, Incompressible>(f, cur, lay, loc, faces, open, F, tau);
        return;
      }
      const int axis = face / 2;
      if (!open[face] || loc[axis] != (face % 2 == 0 ? 0 : lay.extent[axis] - 1)) continue;
      const int s = face % 2 == 0 ? 1 : -1;
      const Face& fc = faces[face];
      if ((fc.type == FaceType::outflow) != (pass == 0)) continue;
      double ug[3] = {0.0, 0.0, 0.0};
      if (fc.type == FaceType::velocity) {
        const long g[3] = {lay.origin[0] + i, lay.origin[1] + j, lay.origin[2] + k};
        fc.velocity(g, axis, ug);
      }
      if (fc.type == FaceType::outflow) {
        const long inner = x + s * (axis == 0 ? 1 : axis == 1 ? lay.padded[0] : lay.padded[0] * lay.padded[1]);
        for (int q = 0; q < L::Q; ++q)
          if (s * L::e[q][axis] > 0) f[q] = cur[q * lay.stride + inner];
      } else if (fc.regularized) {
        long in[3] = {i, j, k};
        in[axis] += s;
        double uin[3];
        post_collision_velocity<L, Incompressible>(&cur[lay.idx(in[0], in[1], in[2])], lay.stride, F, uin);
        regularized<L, Incompressible>(f, axis, s, fc.type == FaceType::velocity, fc.rho, ug, uin, F);
      } else {
        zou_he<L, Incompressible>(f, axis, s, fc.type == FaceType::velocity, fc.rho, ug, F);
      }
    }
}

}  // namespace coflow::fluid::lbm
