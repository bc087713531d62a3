// The lbm core of two fluids (colour gradient, seed 000 §2.3.4) and of fluids
// with interior solids: red and blue populations over one block with its
// ghost layer, the colour field phi = rho_r - rho_b exchanged between ranks
// each step for the colour gradient, half-way bounce-back at every solid cell
// (interior solids and the box's walls), solids coloured by their contact
// angle. One fluid with solids runs as red alone (no blue, no interface).
#pragma once

#include <memory>

#include "coflow/decomposition.hpp"
#include "fluid/lbm/lbm_solver.hpp"

namespace coflow::fluid::lbm {

std::unique_ptr<LbmCore> make_two_phase_core(const Setup& s, const coupler::Decomposition& dec, int rank,
                                             MPI_Comm comm);

}  // namespace coflow::fluid::lbm
