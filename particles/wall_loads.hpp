// series/walls.csv: the mean force the particles exert on each wall over each
// series interval (coupler::ImpulseSeries): the domain faces that are walls
// for the particles (not periodic, not outlets), then the mesh walls of
// particles.walls as mesh0, mesh1, ... in their order.
#pragma once

#include <memory>

#include "coflow/impulse_series.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles {

std::unique_ptr<coupler::ImpulseSeries> make_wall_loads(coupler::Session& s, const ParticleParams& params, long w0);

}  // namespace coflow::particles
