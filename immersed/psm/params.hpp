// immersed.psm: the keys of the partially saturated cells method.
#pragma once

#include "coflow/config.hpp"

namespace coflow::immersed {

struct PsmParams {
  int refinement = 3;     // octree levels for cells cut by a sphere surface
  int centre_lattice = 8; // fractions kept for centres on a lattice of h/N in the cell (0: exact centres)
  int blend_steps = 128;  // the interpolation's weights rounded to multiples of 1/M (0: not rounded)
  bool buoyancy = true;   // add -rho_f V g to each particle (the LBM fluid carries no hydrostatic gradient)
  void visit(config::Visitor& v);
};

}  // namespace coflow::immersed
