#pragma once

#include <memory>

#include "coflow/session.hpp"
#include "fluid/fluid_solver.hpp"

namespace coflow::fluid {

// The fluid section of a validated configuration.
FluidParams read_params(const config::Config& cfg);

// The variant fluid.solver names, read from its subsection, for one block
// (what coflow-fluid runs). setup.cfg and setup.params must outlive it.
std::unique_ptr<FluidSolver> make_solver(const FluidSolver::Setup& setup);

// The fluid component's window loop.
void run(coupler::Session& session);

}  // namespace coflow::fluid
