// Speeds the CFL step (seed 003 eq. 4.1) must allow for before the fluid
// reaches them: the velocity faces' (a lid, a sliding wall, an inlet) and the
// immersed bodies'. Without them a fluid at rest took the whole coupling
// window as its first step, a lid's speed living only in ghosts that the step
// does not read. fv and fv-reference take the same bounds.
#pragma once

#include <algorithm>
#include <array>

#include "coflow/run_config.hpp"
#include "fluid/params.hpp"
#include "immersed/ibm/markers.hpp"

namespace coflow::fluid::fv {

// Per component, the largest |value_c x profile factor| over the velocity
// faces that are not periodic (nor across a one-cell axis), the profile taken at the centres of the face's
// cells at t = 0 (a formula in t is bounded at its start); the value in full,
// whatever its ramp (a ramped face reaches it).
std::array<double, 3> boundary_speeds(const FluidParams& fluid, const config::Config& cfg);

// Per component, the largest marker speed of a set over a window of length
// `window` after its time: |u_c| + |a_c| window.
std::array<double, 3> marker_speeds(const ibm::MarkerSet& markers, double window);

// The speeds a step's CFL limit takes: the fluid's own maxima raised to the
// faces' and the bodies' bounds.
inline void raise_to(double umax[3], const std::array<double, 3>& a, const std::array<double, 3>& b) {
  for (std::size_t d = 0; d < 3; ++d) umax[d] = std::max({umax[d], a[d], b[d]});
}

}  // namespace coflow::fluid::fv
