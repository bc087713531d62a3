// The pointwise pieces of the fv discretisation that fv and fv-reference
// share: the face value of the advection schemes, the IMEX coefficients with
// a variable step, the step from the CFL condition. The loops, ghosts and
// solvers around them are each variant's own.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace coflow::fluid::fv {

// The value a control-volume face carries, from the four values around it
// along the flux (a b | c d, the face between b and c) and the advecting
// velocity U. central: (b + c) / 2. upwind: the upwind value plus half the
// limited difference (van Leer 1974: psi(r) = (r + |r|) / (1 + |r|)), second
// order where the field is smooth and bounded by b and c (no new extrema).
inline double face_value(bool upwind, double a, double b, double c, double d, double U) {
  if (!upwind) return 0.5 * (b + c);
  const double up = U >= 0 ? b : c, down = U >= 0 ? c : b, far = U >= 0 ? a : d;
  const double jump = down - up, back = up - far;
  if (jump * back <= 0.0) return up;  // an extremum (or flat): first order there
  const double r = back / jump;
  return up + 0.5 * jump * (2.0 * r / (1.0 + r));  // van Leer with r > 0
}

// A tangential velocity's ghosts beyond a wall (or velocity face) of value U,
// the parabola through U on the face, u0 and u1 at the first two cell centres
// (h/2 and 3h/2 in), read at -h/2 and -3h/2: second order at the wall and exact
// for a parabolic profile (plane Poiseuille and Couette flow are exact to the
// solver's tolerance). The implicit rows next to a wall scale by 3/4 so that
// the matrix stays symmetric (fv::wall_row_scale).
inline double wall_ghost(double U, double u0, double u1) {
  return (8 * U - 6 * u0 + u1) / 3;
}
inline double wall_ghost2(double U, double u0, double u1) {
  return 8 * U - 9 * u0 + 2 * u1;
}
inline constexpr double wall_row_scale = 0.75;

// One IMEX step (u' = N(u) + L u, N explicit, L implicit) with the step dt
// and the previous one dt_prev (omega = dt / dt_prev):
//   (a0 u^{n+1} - a1 u^n + a2 u^{n-1}) / dt = b0 N^n + b1 N^{n-1}
//                                             + theta L u^{n+1} + (1 - theta) L u^n.
// sbdf2: the variable-step SBDF2 of Wang & Ruuth 2008 (BDF2 with omega, N
// extrapolated linearly; Ascher, Ruuth & Wetton 1995 for the constant step). cnab2: Crank-Nicolson on L,
// Adams-Bashforth 2 on N. first: IMEX Euler (the first step of both).
// e0 u^n + e1 u^{n-1}: a value extrapolated linearly to t^{n+1} (the implicit
// term's wall closure reads one so; for cnab2 b0, b1 reach only t^{n+1/2}).
struct Imex {
  double a0 = 1, a1 = 1, a2 = 0, b0 = 1, b1 = 0, theta = 1, e0 = 1, e1 = 0;
  static Imex first() { return {}; }
  static Imex sbdf2(double omega) {
    return {(1 + 2 * omega) / (1 + omega),
            1 + omega,
            omega * omega / (1 + omega),
            1 + omega,
            -omega,
            1.0,
            1 + omega,
            -omega};
  }
  static Imex cnab2(double omega) { return {1, 1, 0, 1 + 0.5 * omega, -0.5 * omega, 0.5, 1 + omega, -omega}; }
};

// The weights of the momentum source of this step (f, piecewise constant: the
// particles' drag of the coupling window) and of the last step (f_last) in the
// right-hand side of an Imex step: a0 f - a2 (dt_last / dt) f_last. This is
// the IMEX scheme applied to u - I, I the impulse the source has given so far
// (I' = f): the impulse enters exactly, so that fluid and particles exchange
// momentum without loss (seed 003 eq. 5.6) with SBDF2 too (applied as f alone,
// SBDF2 passes on a different impulse: 6 % lost in the two-way case at dt =
// tau_p / 11). For a constant f the weights sum to 1 (the plain source); with
// CNAB2 and the first step they are 1 and 0.
inline std::pair<double, double> source_weights(const Imex& s, double dt, double dt_last) {
  return {s.a0, dt_last > 0 ? -s.a2 * dt_last / dt : 0.0};
}

// The step of the CFL condition (seed 003 eq. 4.1) with the advective limit
// read as 1 / sum_d(max|u_d| / dx_d): eq. 4.2 prints the sum of dx_d / max|u_d|,
// which exceeds the one-axis limit dx / max|u| as soon as two components move;
// the reciprocal sum is the bound of the explicit scheme in several dimensions.
// Infinite for a fluid at rest.
inline double cfl_step(double cfl, const double umax[3], const double h[3], int dims) {
  double rate = 0.0;
  for (int d = 0; d < dims; ++d) rate += umax[d] / h[d];
  return rate > 0 ? cfl / rate : std::numeric_limits<double>::infinity();
}

// The next step towards `remaining` (s) from the limit `limit` and the last
// step: at most twice the last (variable-step SBDF2 is zero-stable for
// omega < 1 + sqrt 2), and the rest of the window split evenly, so that no
// step is a sliver.
inline double next_step(double limit, double last, double remaining) {
  double dt = limit;
  if (last > 0) dt = std::min(dt, 2.0 * last);
  if (!(dt < remaining)) return remaining;
  const double n = std::ceil(remaining / dt * (1 - 1e-12));
  return remaining / n;
}

// The steps of length dt left to `remaining` (s), at least 1. A step that
// would need more than 1e12 of them to end the window is a flow blowing up
// (or a max_step too small): an error, rather than a count beyond a long that
// would end the window in one sliver of a step.
inline long steps_left(double remaining, double dt, const char* who) {
  const double steps = remaining / dt;
  if (!(steps < 1e12))
    throw std::runtime_error(
        fmt::format("{}: a step of {:.3g} s would take {:.3g} steps to the end of the window: the flow is "
                    "blowing up, or fluid.fv.max_step is too small",
                    who, dt, steps));
  return std::max(1L, std::lround(steps));
}

// Steps through a window of length `window` from `time` (which `step`
// advances): each step's length from next_step(limit(), last, what is left),
// recomputed when the limit falls below it, the last step landing on the
// window's end exactly. step(dt, t) takes one step of dt that ends at t and
// sets `time` to t and `last` to dt. limit() is called once more at the
// window's end: it checks the velocity (throws where it is not finite), so
// that a step gone wrong stops the run before the window's output,
// checkpoint and exchanges. fv and fv on the adaptive grid.
template <class Limit, class Step>
void step_window(const double& time, const double& last, double window, Limit&& limit, Step&& step) {
  const double end = time + window;
  long left = 0;
  double dt = 0.0;
  while (end - time > 1e-12 * window) {
    const double most = limit();
    if (left == 0 || dt > most) {
      dt = next_step(most, last, end - time);
      left = steps_left(end - time, dt, "fv");
    }
    step(dt, left == 1 ? end : time + dt);
    if (--left == 0) break;
  }
  limit();
}

// A box without a pressure or outflow face: its velocity faces must let in
// what they let out, or the projection, which takes the right-hand side's
// mean out as round-off, would spread the difference over every cell as a
// uniform divergence (mass made or lost everywhere). `sum`: the Poisson
// right-hand side's sum over all cells, -factor x the divergences'; a mean
// divergence above 1e-12 U / h is no round-off (that is below N eps U / h
// summed). Throws with a message; nothing is checked from rest (U = 0).
inline void check_closed_balance(double sum, double cells, double factor, double velocity_scale,
                                 double hmin) {
  if (!(velocity_scale > 0.0)) return;
  const double mean = -sum / (factor * cells), scale = velocity_scale / hmin;
  if (std::abs(mean) <= 1e-12 * scale) return;
  throw std::runtime_error(fmt::format(
      "fv: the velocity faces let more fluid {} than {} (a mean divergence of {:.3g} 1/s, {:.2g} of U/h) and "
      "no pressure "
      "or outflow face takes up the difference; an incompressible fluid in a closed box needs its velocity "
      "faces "
      "to balance: make a face pressure or outflow, or balance the inflows (their profiles and ramps)",
      mean > 0 ? "out" : "in", mean > 0 ? "in" : "out", mean, std::abs(mean) / scale));
}

}  // namespace coflow::fluid::fv
