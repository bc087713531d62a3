// Lattice Boltzmann collision kernels and the equilibrium: one cell (collide)
// and lines of cells (bgk_line, collide_line), no MPI, no I/O, no allocation.
// The boundary closures are in boundaries.hpp, the partially saturated cells'
// collision in psm_kernel.hpp.
//
// Populations are stored zero-centred: g_q = f_q - w_q, the deviation from the
// rest equilibrium (rho = 1, u = 0). The density is 1 + sum g, the momentum
// sum e g (the weights' first moment vanishes); collision, bounce-back,
// streaming and the Zou-He closure keep their form (w_q = w_opp(q)). A fluid
// at rest with a tiny velocity (seed 003 §5.1: u ~ 1e-10 in lattice units)
// then keeps its momentum to round-off of itself instead of round-off of
// populations of order one.
#pragma once

#include <algorithm>
#include <utility>

#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "fluid/lbm/lattice.hpp"

namespace coflow::fluid::lbm {

// Half a force density F's momentum in population q, 3 w_q (e_q . F) / 2: the
// post-collision populations of a state of velocity u hold rho u + F/2 (Guo,
// Zheng & Shi 2002), so an initial equilibrium at u takes it added.
template <class L>
inline double half_force(int q, const double* F) {
  return 1.5 * L::w[q] * (L::e[q][0] * F[0] + L::e[q][1] * F[1] + L::e[q][2] * F[2]);
}

// Two-relaxation-time collision (Ginzburg 2008): even (symmetric) parts relax
// with tau, fixing the viscosity as BGK does; odd parts with tau_minus, chosen
// from the magic parameter Lambda = (tau - 1/2)(tau_minus - 1/2). BGK is
// tau_minus = tau.
struct CollisionParams {
  double tau = 0.8;
  double omega = 1.25;          // 1 / tau (even moments)
  double omega_minus = 1.25;    // 1 / tau_minus (odd moments)
  double force_plus = 0.0;      // 1 - omega / 2 (Guo forcing, even part)
  double force_minus = 0.0;     // 1 - omega_minus / 2 (odd part)
};

inline CollisionParams collision_params(double tau, bool trt = false, double magic = 0.1875) {
  const double tau_minus = trt ? 0.5 + magic / (tau - 0.5) : tau;
  return {tau, 1.0 / tau, 1.0 / tau_minus, 1.0 - 0.5 / tau, 1.0 - 0.5 / tau_minus};
}

// Both populations of the pair (q, opp(q)) after the TRT collision with Guo
// forcing (its source split the same way: even part 9 w (e.u)(e.F) - 3 w u.F,
// odd part 3 w e.F). The equilibrium w (e0 + c45 (e.u)^2 + c3 e.u) comes with
// the cell's terms folded: e0 = rho - 1.5 rho_m u^2, c45 = 4.5 rho_m,
// c3 = 3 rho_m. Zero-centred: rho is the deviation rho - 1, rho_m the density
// of the momentum (1 for He-Luo). T: double for one cell, Vec4 for four (the
// line kernels below).
template <class T>
[[gnu::always_inline]] inline void trt_pair(T& fq, T& fo, double w, T e0, T c45, T c3, T eu, double eF, T uF,
                                            const CollisionParams& p) {
  const T plus = 0.5 * (fq + fo), minus = 0.5 * (fq - fo);
  const T feq_plus = w * (e0 + c45 * eu * eu);
  const T feq_minus = w * c3 * eu;
  const T s_plus = (p.force_plus * w) * (9.0 * eF * eu - 3.0 * uF);
  const double s_minus = p.force_minus * w * 3.0 * eF;
  const T even = p.omega * (plus - feq_plus) - s_plus;
  const T odd = p.omega_minus * (minus - feq_minus) - s_minus;
  fq = fq - even - odd;
  fo = fo - even + odd;
}

// BGK/TRT collision with Guo forcing on the populations f of one cell, in place.
// Equilibrium: seed 000 eq. 2.33 (standard, rho_m = rho) or eq. 2.47 / c_s^2
// (He & Luo incompressible, rho_m = rho_0 = 1); collision eqs 2.42 / 2.45.
// F: force density (lattice units). Returns u^2 of the cell (for the Mach check).
template <class L, bool Incompressible>
inline double collide(double* f, const CollisionParams& p, const double* F) {
  double rho = 0.0, jx = 0.0, jy = 0.0, jz = 0.0;  // rho: the deviation rho - 1
  for (int q = 0; q < L::Q; ++q) {
    rho += f[q];
    jx += L::e[q][0] * f[q];
    jy += L::e[q][1] * f[q];
    jz += L::e[q][2] * f[q];
  }
  const double rho_m = Incompressible ? 1.0 : 1.0 + rho;
  const double inv = Incompressible ? 1.0 : 1.0 / rho_m;
  const double ux = (jx + 0.5 * F[0]) * inv, uy = (jy + 0.5 * F[1]) * inv, uz = (jz + 0.5 * F[2]) * inv;
  const double uu = ux * ux + uy * uy + uz * uz;
  const double uF = ux * F[0] + uy * F[1] + uz * F[2];
  const double e0 = rho - 1.5 * rho_m * uu, c45 = 4.5 * rho_m, c3 = 3.0 * rho_m;
  // Pairs (q, opp q) for the moving populations; the rest population takes the
  // mass the others leave, so that rounding cannot bias the total mass.
  double moving = 0.0;
  for (int q = 1; q < L::Q; ++q) {
    const int o = L::opp[q];
    if (o < q) continue;
    const double eu = L::e[q][0] * ux + L::e[q][1] * uy + L::e[q][2] * uz;
    const double eF = L::e[q][0] * F[0] + L::e[q][1] * F[1] + L::e[q][2] * F[2];
    trt_pair(f[q], f[o], L::w[q], e0, c45, c3, eu, eF, uF, p);
    moving += f[q] + f[o];
  }
  f[0] = rho - moving;  // g_0 = (rho - 1) - sum of the others
  return uu;
}

// Four doubles as one value (the GCC/Clang vector extension: one AVX
// instruction per operation, SSE pairs without AVX). The kernels below are
// written on it rather than left to the auto-vectoriser, whose choice for the
// old loop nest changed with the code around it: the same source ran scalar
// (22 MLUPS) or vectorised (65 MLUPS).
using Vec4 = double __attribute__((vector_size(32)));

// The larger of a and b, and NaN once either is (the Mach check must see a NaN
// in any cell): for u^2 of one cell, or of four lanes at once.
[[gnu::always_inline]] inline double nan_max(double a, double b) { return (b > a || b != b) ? b : a; }
[[gnu::always_inline]] inline Vec4 nan_max(Vec4 a, Vec4 b) { return ((b > a) | (b != b)) ? b : a; }

namespace detail {
template <class L, int q>
[[gnu::always_inline]] inline Vec4 e_dot(Vec4 x, Vec4 y, Vec4 z) {
  Vec4 s = {0.0, 0.0, 0.0, 0.0};
  if constexpr (L::e[q][0] != 0) s = L::e[q][0] > 0 ? s + x : s - x;
  if constexpr (L::e[q][1] != 0) s = L::e[q][1] > 0 ? s + y : s - y;
  if constexpr (L::e[q][2] != 0) s = L::e[q][2] > 0 ? s + z : s - z;
  return s;
}

template <class L, int q>
[[gnu::always_inline]] inline void add_moment(Vec4 f, Vec4& rho, Vec4& jx, Vec4& jy, Vec4& jz) {
  rho += f;
  if constexpr (L::e[q][0] == 1) jx += f;
  if constexpr (L::e[q][0] == -1) jx -= f;
  if constexpr (L::e[q][1] == 1) jy += f;
  if constexpr (L::e[q][1] == -1) jy -= f;
  if constexpr (L::e[q][2] == 1) jz += f;
  if constexpr (L::e[q][2] == -1) jz -= f;
}

}  // namespace detail

// Where the line kernels below find the populations of one row: in<q>(i) is
// population q as pulled by cell i of the row (and the three cells after it),
// out<q>(i) where cell i's post-collision population q goes.
//
// LineRef: populations any stride n apart. Its 2 Q stream addresses (38 for
// D3Q19) do not fit the core's 16 general registers, so a kernel on it loads
// most of them from the stack for every access.
struct LineRef {
  const double* src;  // the row's first cell in the array read
  double* dst;        // and in the array written
  long n;             // stride between populations
  const long* off;    // pull offsets
  template <int q>
  [[gnu::always_inline]] const double* in(long i) const { return src + q * n + i - off[q]; }
  template <int q>
  [[gnu::always_inline]] double* out(long i) const { return dst + q * n + i; }
};

// How far ahead (in values: cells here, half as many cells in the two-phase
// core's pairs) the line kernels prefetch the populations they pull: eight
// cache lines, measured best on a Zen 3 core (32-64 equal, 96 and
// more slower; none 5 % slower).
inline constexpr long prefetch_ahead = 64;

// The prefetch of a population every kernel pulls, into every cache level
// (T0). With non-temporal prefetches (NTA), which on Intel cores leave a line
// in L1 only, the BGK kernel ran at 0.48-0.51 of its speed on a Xeon VM (30.8
// against 63.8 MLUPS at 256^3, bench-lbm, 2026-11-26) and the colour-gradient
// kernel, whose two passes pull the same lines, at 0.26-0.39; on the Zen 3
// core T0 and NTA measured alike.
[[gnu::always_inline]] inline void prefetch_pulled(const double* p) { __builtin_prefetch(p, 0, 3); }

// The stride of SpacedRef: 2^25 doubles and 37 cache lines (with a power of two
// the 38 streams would share cache sets). Blocks of up to this many cells
// (ghosts and padding included) use it.
inline constexpr long spaced_stride = (1L << 25) + 37 * 8;

namespace detail {
// The populations of a lattice by the neighbour row they are pulled from
// (their (e_y, e_z): nine rows for D3Q19, three for D2Q9), each group reached
// from a pointer at its middle population.
template <class L>
struct RowGroups {
  int count = 0;
  int of[L::Q] = {};      // group of population q
  int first[L::Q] = {};   // a population of group g (for its row offset)
  int centre[L::Q] = {};  // the population group g's pointer is at
  int reach = 0;          // largest |q - centre| (in strides)
};

template <class L>
constexpr RowGroups<L> row_groups() {
  RowGroups<L> r;
  for (int q = 0; q < L::Q; ++q) {
    int g = 0;
    while (g < r.count && (L::e[r.first[g]][1] != L::e[q][1] || L::e[r.first[g]][2] != L::e[q][2])) ++g;
    if (g == r.count) r.first[r.count++] = q;
    r.of[q] = g;
  }
  for (int g = 0; g < r.count; ++g) {
    int lo = L::Q, hi = -1;
    for (int q = 0; q < L::Q; ++q)
      if (r.of[q] == g) {
        lo = q < lo ? q : lo;
        hi = q > hi ? q : hi;
      }
    r.centre[g] = (lo + hi) / 2;
    r.reach = std::max({r.reach, r.centre[g] - lo, hi - r.centre[g]});
  }
  return r;
}
}  // namespace detail

// SpacedRef: populations spaced_stride apart. The populations pulled from one
// neighbour row then lie at constant distances from one pointer, and the
// stores of 15 consecutive populations from another: 9 + 2 registers for
// D3Q19 instead of 38 addresses (x86 displacements reach +-2 GiB, 7 strides).
template <class L>
struct SpacedRef {
  static constexpr detail::RowGroups<L> groups = detail::row_groups<L>();
  static constexpr int span = 15;  // populations per store pointer
  // the population store pointer s is at (inside the arrays)
  static constexpr int store_centre(int s) { return std::min(s * span + span / 2, L::Q - 1); }
  static_assert(std::max(groups.reach, span / 2) * spaced_stride * 8 + 8 * (prefetch_ahead + 8) < (1L << 31),
                "SpacedRef: a population beyond a 32-bit displacement");
  const double* row[groups.count];
  double* put[(L::Q + span - 1) / span];

  // The row starting at cell `base` of the arrays src and dst (stride
  // spaced_stride), with the pull offsets off.
  SpacedRef(const double* src, double* dst, long base, const long* off) {
    for (int g = 0; g < groups.count; ++g) {
      const int q = groups.first[g];
      row[g] = src + base + groups.centre[g] * spaced_stride - (off[q] - L::e[q][0]);
    }
    for (int s = 0; s < (L::Q + span - 1) / span; ++s) put[s] = dst + base + store_centre(s) * spaced_stride;
  }
  template <int q>
  [[gnu::always_inline]] const double* in(long i) const {
    constexpr int g = groups.of[q];
    return row[g] + i + ((q - groups.centre[g]) * spaced_stride - L::e[q][0]);
  }
  template <int q>
  [[gnu::always_inline]] double* out(long i) const {
    return put[q / span] + i + (q - store_centre(q / span)) * spaced_stride;
  }
};

// One cache line of the lean path: BGK without a force (tau_minus = tau,
// F = 0), the collision of seed 000 eqs 2.33 / 2.47 and 2.42, on the eight
// cells i..i+7 of a row (R: LineRef or SpacedRef).
//
// Written for a core that is short of registers: the moments are summed as
// the populations arrive, and the relaxation reads each pair again (from L1)
// and stores both halves of its two cache lines at once (streaming stores when
// `Stream`: a line written half now and half later costs a read-modify-write
// in memory). The equilibrium is folded to fewer values per cell: with
// v = 3 omega j and k = 1 / (2 omega rho_m),
//   omega feq_q = w_q (E0 + k (e_q.v)^2 + e_q.v),  E0 = omega rho - k v^2 / 3
// (rho: the deviation rho - 1), and the zero and unit lattice components are
// folded at compile time. Same results as collide() up to round-off.
namespace detail {
struct LineCells {  // four cells' values: v = 3 omega j, k, E0 (see above)
  Vec4 rho, vx, vy, vz, k, e0, moving;
};

[[gnu::always_inline]] inline Vec4 get(const double* p) {
  Vec4 v;
  __builtin_memcpy(&v, p, sizeof(Vec4));
  return v;
}

template <class L, class R, int... qs>
[[gnu::always_inline]] inline void line_moments(const R& r, long i, Vec4& rho, Vec4& jx, Vec4& jy, Vec4& jz,
                                                std::integer_sequence<int, qs...>) {
  (add_moment<L, qs>(get(r.template in<qs>(i)), rho, jx, jy, jz), ...);
}

template <class R, int... qs>
[[gnu::always_inline]] inline void line_prefetch(const R& r, long i, std::integer_sequence<int, qs...>) {
  (prefetch_pulled(r.template in<qs>(i + prefetch_ahead)), ...);
}

template <class L, bool Incompressible, class R>
[[gnu::always_inline]] inline LineCells line_cells(const R& r, long i, double omega) {
  const Vec4 zero = {0.0, 0.0, 0.0, 0.0};
  LineCells c{zero, zero, zero, zero, zero, zero, zero};
  line_moments<L>(r, i, c.rho, c.vx, c.vy, c.vz, std::make_integer_sequence<int, L::Q>{});
  c.vx *= 3.0 * omega;
  c.vy *= 3.0 * omega;
  c.vz *= 3.0 * omega;
  if constexpr (Incompressible)
    c.k = zero + 0.5 / omega;  // rho_m = rho_0 = 1
  else
    c.k = (0.5 / omega) / (1.0 + c.rho);
  c.e0 = omega * c.rho - (1.0 / 3.0) * (c.k * (c.vx * c.vx + c.vy * c.vy + c.vz * c.vz));
  return c;
}

template <bool Stream>
[[gnu::always_inline]] inline void put(double* p, Vec4 v) {
#if defined(__AVX__)
  if constexpr (Stream) {
    _mm256_stream_pd(p, v);
    return;
  }
#endif
  __builtin_memcpy(p, &v, sizeof(Vec4));
}

// Populations q and o (pulled) of the four cells from i.
template <int q, int o, class R>
[[gnu::always_inline]] inline void get_pair(const R& r, long i, Vec4& gq, Vec4& go) {
  gq = get(r.template in<q>(i));
  go = get(r.template in<o>(i));
}

// The cache lines of q and o at i, both halves of each stored together.
template <bool Stream, int q, int o, class R>
[[gnu::always_inline]] inline void put_pair(const R& r, long i, const Vec4 (&fq)[2], const Vec4 (&fo)[2]) {
  put<Stream>(r.template out<q>(i), fq[0]);
  put<Stream>(r.template out<q>(i + 4), fq[1]);
  put<Stream>(r.template out<o>(i), fo[0]);
  put<Stream>(r.template out<o>(i + 4), fo[1]);
}

template <class L, bool Stream, int q, class R>
[[gnu::always_inline]] inline void line_pair(const R& r, long i, double keep, LineCells (&c)[2]) {
  constexpr int o = L::opp[q];
  if constexpr (q > 0 && o > q) {
    constexpr double w = L::w[q];
    Vec4 fq[2], fo[2];
    for (int h = 0; h < 2; ++h) {
      Vec4 gq, go;
      get_pair<q, o>(r, i + 4 * h, gq, go);
      const Vec4 ev = e_dot<L, q>(c[h].vx, c[h].vy, c[h].vz);
      const Vec4 even = w * (c[h].e0 + c[h].k * (ev * ev));
      const Vec4 odd = w * ev;
      fq[h] = keep * gq + (even + odd);
      fo[h] = keep * go + (even - odd);
      c[h].moving += fq[h] + fo[h];
    }
    put_pair<Stream, q, o>(r, i, fq, fo);
  }
}

template <class L, bool Stream, class R, int... qs>
[[gnu::always_inline]] inline void line_relax(const R& r, long i, double keep, LineCells (&c)[2],
                                              std::integer_sequence<int, qs...>) {
  (line_pair<L, Stream, qs>(r, i, keep, c), ...);
}
}  // namespace detail

// Returns the larger u^2 of each lane (NaN if any cell's is NaN).
template <class L, bool Incompressible, bool Stream, class R>
[[gnu::always_inline]] inline Vec4 bgk_line(const R& r, long i, double omega) {
  detail::line_prefetch(r, i, std::make_integer_sequence<int, L::Q>{});
  detail::LineCells c[2] = {detail::line_cells<L, Incompressible>(r, i, omega),
                            detail::line_cells<L, Incompressible>(r, i + 4, omega)};
  detail::line_relax<L, Stream>(r, i, 1.0 - omega, c, std::make_integer_sequence<int, L::Q>{});
  // The rest population takes the mass the others leave (as in collide()).
  detail::put<Stream>(r.template out<0>(i), c[0].rho - c[0].moving);
  detail::put<Stream>(r.template out<0>(i + 4), c[1].rho - c[1].moving);
  // u^2 = v^2 (2 k / 3)^2, after the relaxation (registers are short)
  Vec4 uu[2];
  for (int h = 0; h < 2; ++h) {
    const Vec4 s = (2.0 / 3.0) * c[h].k;
    uu[h] = (c[h].vx * c[h].vx + c[h].vy * c[h].vy + c[h].vz * c[h].vz) * (s * s);
  }
  return nan_max(uu[0], uu[1]);
}

// The same by cache line for the general collision (TRT, Guo forcing with
// the force F the same on all eight cells): collide() on cells i..i+7.
namespace detail {
struct TrtCells {
  Vec4 rho, ux, uy, uz, uF, e0, c45, c3, moving;  // e0, c45, c3: see trt_pair
};

template <class L, bool Incompressible, class R>
[[gnu::always_inline]] inline TrtCells trt_cells(const R& r, long i, const double* F) {
  const Vec4 zero = {0.0, 0.0, 0.0, 0.0};
  TrtCells c{zero, zero, zero, zero, zero, zero, zero, zero, zero};
  line_moments<L>(r, i, c.rho, c.ux, c.uy, c.uz, std::make_integer_sequence<int, L::Q>{});
  const Vec4 rho_m = Incompressible ? zero + 1.0 : 1.0 + c.rho;
  c.ux += 0.5 * F[0];
  c.uy += 0.5 * F[1];
  c.uz += 0.5 * F[2];
  if constexpr (!Incompressible) {
    const Vec4 inv = 1.0 / rho_m;
    c.ux *= inv;
    c.uy *= inv;
    c.uz *= inv;
  }
  const Vec4 uu = c.ux * c.ux + c.uy * c.uy + c.uz * c.uz;
  c.uF = c.ux * F[0] + c.uy * F[1] + c.uz * F[2];
  c.e0 = c.rho - 1.5 * rho_m * uu;
  c.c45 = 4.5 * rho_m;
  c.c3 = 3.0 * rho_m;
  return c;
}

template <class L, bool Stream, int q, class R>
[[gnu::always_inline]] inline void trt_line_pair(const R& r, long i, const CollisionParams& p, const double* F,
                                                 TrtCells (&c)[2]) {
  constexpr int o = L::opp[q];
  if constexpr (q > 0 && o > q) {
    constexpr double w = L::w[q];
    const double eF = L::e[q][0] * F[0] + L::e[q][1] * F[1] + L::e[q][2] * F[2];
    Vec4 fq[2], fo[2];
    for (int h = 0; h < 2; ++h) {
      Vec4 gq, go;
      get_pair<q, o>(r, i + 4 * h, gq, go);
      const Vec4 eu = e_dot<L, q>(c[h].ux, c[h].uy, c[h].uz);
      trt_pair(gq, go, w, c[h].e0, c[h].c45, c[h].c3, eu, eF, c[h].uF, p);
      fq[h] = gq;
      fo[h] = go;
      c[h].moving += gq + go;
    }
    put_pair<Stream, q, o>(r, i, fq, fo);
  }
}

template <class L, bool Stream, class R, int... qs>
[[gnu::always_inline]] inline void trt_line_relax(const R& r, long i, const CollisionParams& p, const double* F,
                                                  TrtCells (&c)[2], std::integer_sequence<int, qs...>) {
  (trt_line_pair<L, Stream, qs>(r, i, p, F, c), ...);
}
}  // namespace detail

// Returns the larger u^2 of each lane (NaN if any cell's is NaN).
template <class L, bool Incompressible, bool Stream, class R>
[[gnu::always_inline]] inline Vec4 collide_line(const R& r, long i, const CollisionParams& p, const double* F) {
  detail::line_prefetch(r, i, std::make_integer_sequence<int, L::Q>{});
  detail::TrtCells c[2] = {detail::trt_cells<L, Incompressible>(r, i, F),
                           detail::trt_cells<L, Incompressible>(r, i + 4, F)};
  detail::trt_line_relax<L, Stream>(r, i, p, F, c, std::make_integer_sequence<int, L::Q>{});
  detail::put<Stream>(r.template out<0>(i), c[0].rho - c[0].moving);
  detail::put<Stream>(r.template out<0>(i + 4), c[1].rho - c[1].moving);
  // u^2 again rather than held through the relaxation (one register fewer)
  Vec4 uu[2];
  for (int h = 0; h < 2; ++h) uu[h] = c[h].ux * c[h].ux + c[h].uy * c[h].uy + c[h].uz * c[h].uz;
  return nan_max(uu[0], uu[1]);
}

// Zero-centred equilibrium g_q = feq_q - w_q for the density rho (the density
// itself, not its deviation) and velocity u.
template <class L, bool Incompressible>
inline double equilibrium(int q, double rho, const double* u) {
  const double eu = L::e[q][0] * u[0] + L::e[q][1] * u[1] + L::e[q][2] * u[2];
  const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  const double rho_m = Incompressible ? 1.0 : rho;
  return L::w[q] * ((rho - 1.0) + rho_m * (3.0 * eu + 4.5 * eu * eu - 1.5 * uu));
}

}  // namespace coflow::fluid::lbm
