// point: unresolved (point) particles on the fluid grid, seed 003 §3.2 and
// §4.2.2. Each window this component
//   1. receives the fluid's velocity, k and epsilon (a ghost layer of 2 cells),
//      and computes the vorticity by central differences,
//   2. receives the particle states (routed to the rank owning the position),
//      interpolates u, vorticity, k and epsilon trilinearly from the cell
//      centres, adds the fluid's density and viscosity, and returns them,
//   3. after the particles' sub-steps, receives each particle's impulse of the
//      fluid forces over the window and spreads -impulse / (window V_cell) onto
//      the 8 cells around it with the same trilinear weights (eq. 3.43 averaged
//      over the sub-steps; the sum over cells equals the sum over particles),
//   4. sends that momentum source to the fluid, which applies it in the
//      window's step.
// At each window's end the fluid has taken exactly the momentum the particles
// lost to it, so fluid + particles is conserved to round-off.
#pragma once

#include <memory>
#include <string>

#include "coflow/window_loop.hpp"
#include "immersed/immersed_interface.hpp"
#include "immersed/point/params.hpp"

namespace coflow::immersed {

// The point method's part of each window (steps 1-4 above), for a run of its
// own or beside ibm's bodies (immersed.ibm.particles: point); its totals go to
// series/<series>.csv. Needs the fluid and particles partners; call it after
// the window is negotiated.
std::unique_ptr<coupler::WindowParts> make_point_windows(coupler::Session& s, const std::string& series);

class PointMethod final : public ImmersedMethod {
 public:
  using Params = PointParams;
  PointMethod(const Setup& setup, const Params& params) : setup_(setup), p_(params) {}
  void run(coupler::Session& s) override;

 private:
  Setup setup_;
  Params p_;
};

}  // namespace coflow::immersed
