// psm's check of the particle records it receives: a particle that has blown
// up (a position far outside the box, or not a number) stops the run with its
// id. Covering it would take a loop per period crossed for each of its cells,
// or cast a position past the range of a cell index.
#pragma once

#include <fmt/format.h>

#include <cmath>

#include "coflow/protocol.hpp"
#include "coflow/run_config.hpp"
#include "coflow/session.hpp"

namespace coflow::immersed::psm {

// Throws SolverError unless the radius is positive, the velocities finite and
// the centre within one box length (and the radius) of the box on every axis
// (dem keeps its particles in the box, wrapping periodic axes).
inline void check_record(const protocol::ParticleRecord& r, const config::DomainParams& dom) {
  bool sane = std::isfinite(r.radius) && r.radius > 0.0;
  for (int d = 0; d < 3; ++d) {
    const double length = dom.upper[d] - dom.lower[d];
    const double lo = dom.lower[d] - length - r.radius, hi = dom.upper[d] + length + r.radius;
    sane = sane && r.x[d] >= lo && r.x[d] <= hi && std::isfinite(r.v[d]) && std::isfinite(r.w[d]);
  }
  if (!sane)
    throw coupler::SolverError(fmt::format(
        "psm: particle {} has position ({:.6g}, {:.6g}, {:.6g}) m, radius {:.6g} m and velocity ({:.6g}, "
        "{:.6g}, {:.6g}) m/s: it is far outside the box or not a number (it has blown up); reduce the "
        "particles' time step or the contact stiffness",
        r.id, r.x[0], r.x[1], r.x[2], r.radius, r.v[0], r.v[1], r.v[2]));
}

}  // namespace coflow::immersed::psm
