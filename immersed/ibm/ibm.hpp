// ibm: bodies given as triangle meshes made real for the fluid by the
// multi-direct-forcing immersed boundary (seed 003 §4.2.1). This component
// owns the geometry: it samples each mesh into markers about a cell apart
// (ibm/markers.hpp) and moves them as the bodies' prescribed motions say. Each
// window it
//   1. sends the markers to every fluid rank while a body moves; when none
//      moves, in the first window only, marked the last: the fluid iterates
//      the forcing alone inside its steps (ibm/direct_forcing.hpp),
//   2. receives, after the fluid's step, the mean force and torque on each
//      body over the window, the most forcing iterations and the largest slip
//      left, and writes them to series/immersed.csv.
#pragma once

#include "immersed/ibm/params.hpp"
#include "immersed/immersed_interface.hpp"

namespace coflow::immersed {

class IbmMethod final : public ImmersedMethod {
 public:
  using Params = IbmParams;
  IbmMethod(const Setup& setup, const Params& params) : setup_(setup), p_(params) {}
  void run(coupler::Session& s) override;

 private:
  Setup setup_;
  Params p_;
};

}  // namespace coflow::immersed
