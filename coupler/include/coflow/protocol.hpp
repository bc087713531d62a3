// What the built-in components exchange each coupling window (docs/protocol.md
// §4): record layouts and message tags.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace coflow::protocol {

// The version of what the components exchange (record layouts, tags, the
// sparse messages and their replies). Discovery refuses a launch whose
// components were built with different versions (an external component built
// against another coflow). Raise it with every change a peer would misread.
//   1: until 2026-11-28 (never announced: builds before the check leave
//      padding, usually 0, where the version now sits, and do not check);
//   2: since 2026-11-29, sparse records carry the receiver's int32 local index,
//      the fluid's force on psm cells comes back as replies (tag + 2), one
//      fluid gets 4 solid values a cell.
// A mismatch aborts the whole launch (MPI_Abort): a build without the check
// would not stop by itself.
inline constexpr std::uint32_t kVersion = 2;

// particles -> immersed: one record per particle, routed by position.
struct ParticleRecord {
  std::int64_t id;
  double x[3], v[3], w[3];  // position, velocity, angular velocity
  double radius;
  double mass;
  double contact_angle;  // degrees, of the red fluid on the particle's species (-1: the fluid's own)
};
// immersed -> particles: the hydrodynamic load on each record (N, N m); the
// copies of a particle held by several immersed ranks are summed (psm: the
// rank owning the centre sends the whole load, the others zero).
struct ParticleLoad {
  double force[3];
  double torque[3];
};
static_assert(sizeof(ParticleLoad) == 6 * sizeof(double), "read as six doubles (check_finite)");

inline void add_load(std::byte* into, const std::byte* from) {
  ParticleLoad a, b;
  std::memcpy(&a, into, sizeof a);
  std::memcpy(&b, from, sizeof b);
  for (int k = 0; k < 3; ++k) {
    a.force[k] += b.force[k];
    a.torque[k] += b.torque[k];
  }
  std::memcpy(into, &a, sizeof a);
}

// immersed -> particles (method point): the fluid at each particle, and at each
// probe point the particles sent after them, interpolated from the grid; one
// copy per record (no ghost copies).
struct FluidAtParticle {
  double u[3];
  double vorticity[3];
  double k, epsilon;
  double rho, mu;
};
// particles -> immersed (method point), after the sub-steps: the impulse of the
// fluid forces on each particle over the window (N s), routed by the position
// at the window's end, where it is spread onto the grid, with ghost copies
// kImpulseGhost cells wide (each immersed rank spreads into its own cells only:
// a sender without the copies loses the stencil's corners across immersed
// blocks, unseen); then one record per
// particle that left through an outlet in the window, at its last position
// inside, with its impulse until it left.
struct ParticleImpulse {
  std::int64_t id;
  double x[3];
  double impulse[3];
};

// immersed -> fluid (method psm), per covered cell: the solid fraction, the
// solid velocity (m/s) and, for a two-phase fluid, the grains' wetting (the
// fraction-weighted cos of their contact angle).
inline constexpr int solid_values(bool two_phase) {
  return two_phase ? 5 : 4;
}

// Message tags on the intercommunicators.
inline constexpr int kTagParticles = 1000;   // particles <-> immersed point exchange
inline constexpr int kTagSolid = 1100;       // immersed -> fluid: solid_values() per cell; the
                                             // replies: the force on the solid (3 per cell)
inline constexpr int kTagFlow = 1300;        // fluid -> immersed: u[3], k, epsilon per cell (point)
inline constexpr int kTagSource = 1400;      // immersed -> fluid: momentum source, N/m^3 (point)
inline constexpr int kTagImpulse = 1500;     // particles -> immersed: impulses (point)
// The impulses' ghost copies (point): one cell, the reach of a particle's
// trilinear stencil beyond the cell holding it.
inline constexpr int kImpulseGhost = 1;
inline constexpr int kTagBodyLoads = 1600;   // fluid -> immersed: loads on the ibm bodies, mdf iterations, slip

}  // namespace coflow::protocol
