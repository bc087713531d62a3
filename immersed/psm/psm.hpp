// psm: resolved particles on the fluid grid through Noble & Torczynski's
// partially saturated cells (seed 000 §2.4). Each window this component
//   1. receives the particle states (routed by position, with a ghost layer wide
//      enough for every cell a particle covers),
//   2. computes each owned cell's solid fraction per covering particle (exact
//      for cells wholly inside or outside a sphere, adaptive octree sub-division
//      of the others, kept per centre offset: fractions.hpp), the cell's total
//      fraction (clamped at 1) and its solid
//      velocity v + omega x (x_cell - x_p), fraction-weighted over the particles,
//   3. sends those cells to the fluid, which collides them with eq. 2.66, with
//      the fraction-weighted cos(contact angle) of the particles' species (a
//      two-phase fluid colours the cells with it; -1 in a species: the
//      fluid.two_phase.contact_angle),
//   4. receives the force the fluid exerted on the solid in each of them, and
//   5. returns to each particle its share (by fraction) of the force in the cells
//      it covers, and the torque of those shares about its centre (eqs 2.70-2.71):
//      the rank owning the particle's centre sums them all, in the order it
//      covers them, with the cells other ranks own through a halo
//      (cell_halo.hpp); the ranks holding a ghost copy return zero. Particles
//      are covered in the order of their ids. A particle's load is thus the
//      same, bit for bit, for any number of immersed and particle ranks (and
//      of lbm's ranks: validation.psm_ranks_1_vs_16).
#pragma once

#include <array>
#include <vector>

#include "immersed/immersed_interface.hpp"
#include "immersed/psm/fractions.hpp"
#include "immersed/psm/params.hpp"

namespace coflow::immersed {

class PsmMethod final : public ImmersedMethod {
 public:
  using Params = PsmParams;
  PsmMethod(const Setup& setup, const Params& params) : setup_(setup), p_(params) {}
  void run(coupler::Session& s) override;

 private:
  Setup setup_;
  Params p_;
};

}  // namespace coflow::immersed
