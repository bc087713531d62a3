// Speeds the CFL step (seed 003 eq. 4.1) allows for in the first window of a
// run, before the fluid reaches them: the velocity faces' (a lid, a sliding
// wall, an inlet) and the immersed bodies'. Without them a fluid at rest took
// the whole coupling window as its first step, a lid's speed living only in
// ghosts that the step does not read. From the second window on the fluid's
// own speeds rule (each step at most twice the last), so a restart, which
// never repeats the first window, steps as the run it goes on from. fv,
// fv-reference and the adaptive grid take the same bounds.
#pragma once

#include <algorithm>
#include <array>

#include "coflow/run_config.hpp"
#include "fluid/params.hpp"
#include "immersed/ibm/markers.hpp"

namespace coflow::fluid::fv {

// Per component, the largest |value_c x profile factor| over the velocity
// faces that are not periodic (nor across a one-cell axis), the profile taken
// at the face's cell centres and cell corners (where the tangential
// components sit) at t = 0 (a formula in t is bounded at its start); the
// value in full, whatever its ramp.
std::array<double, 3> boundary_speeds(const FluidParams& fluid, const config::Config& cfg);

// Per component, the largest |u_c| and |a_c| of a set of markers: over a
// window of length w after the set's time they move at most |u_c| + |a_c| w.
struct MarkerSpeeds {
  std::array<double, 3> u{0.0, 0.0, 0.0}, a{0.0, 0.0, 0.0};
  std::array<double, 3> over(double w) const { return {u[0] + a[0] * w, u[1] + a[1] * w, u[2] + a[2] * w}; }
};
MarkerSpeeds marker_speeds(const ibm::MarkerSet& markers);

// The speeds a step's CFL limit takes in a run's first window: the fluid's
// own maxima raised to the faces' and the bodies' bounds.
inline void raise_to(double umax[3], const std::array<double, 3>& a, const std::array<double, 3>& b) {
  for (std::size_t d = 0; d < 3; ++d) umax[d] = std::max({umax[d], a[d], b[d]});
}

}  // namespace coflow::fluid::fv
