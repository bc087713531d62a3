// Soft-sphere contact law of seed 000 §2.2.2: one contact, no MPI, no I/O.
#pragma once

#include <fmt/format.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "coflow/clock.hpp"

namespace coflow::particles::dem {

using V3 = Eigen::Vector3d;

struct ContactLaw {
  double kn = 1e4;       // K_N, N/m
  double ks = 1e4;       // k_S, N/m
  double mu = 0.5;       // Coulomb friction
  double sigma_c = 0.0;  // bond strengths, Pa (eq. 2.15)
  double sigma_t = 0.0;
  double tau_c = 0.0;
};

// What a contact remembers between steps.
struct ContactState {
  V3 shear = V3::Zero();  // stored shear force on particle 1, N
  bool bonded = false;
  long seen = -1;         // last step it was evaluated (bookkeeping)
  V3 normal = V3::Zero(); // mesh walls: the direction of the contact, to follow it across triangles
};

enum class Failure { none, tension, compression, shear };

struct ContactForce {
  V3 force = V3::Zero();    // on particle 1 (particle 2 gets -force)
  V3 torque1 = V3::Zero();  // about the centre of 1
  V3 torque2 = V3::Zero();  // about the centre of 2
  bool active = false;      // false: no contact (history to be dropped)
  Failure failure = Failure::none;
  double failure_normal = 0.0;  // on failure: the normal force (> 0 compressive) and
  double failure_shear = 0.0;   // the shear force magnitude that broke the bond, N
};

// n: unit normal from 2 to 1; overlap U_N (eq. 2.13, < 0 is a gap); a1, a2:
// distances from the centres to the contact point along -n and +n; vrel: velocity
// of the contact point of 1 relative to that of 2; R_sum = R1 + R2 for the bond
// strengths (eq. 2.15); dt: time step.
inline ContactForce contact_force(const V3& n, double overlap, double a1, double a2, const V3& vrel,
                                  double r_sum, ContactState& s, const ContactLaw& law, double dt) {
  ContactForce out;
  if (overlap <= 0.0 && !s.bonded) {
    s.shear.setZero();
    return out;  // apart and not cemented: no force (eq. 2.16)
  }
  out.active = true;
  // The stored shear force turns with the contact plane: project it onto the new
  // plane and keep its magnitude.
  const double before2 = s.shear.squaredNorm();
  if (before2 > 0.0) {
    s.shear -= s.shear.dot(n) * n;
    const double after2 = s.shear.squaredNorm();
    if (after2 > 0.0) s.shear *= std::sqrt(before2 / after2);
  }
  // Incremental shear spring (eq. 2.14), opposing the sliding velocity.
  const V3 vs = vrel - vrel.dot(n) * n;
  s.shear -= law.ks * dt * vs;
  // Normal spring (eq. 2.12); tension only while bonded.
  const double fn = law.kn * overlap;
  if (s.bonded) {
    const double r2 = r_sum * r_sum;
    if (fn < 0.0 && -fn > law.sigma_t * r2)
      out.failure = Failure::tension;
    else if (fn > 0.0 && fn > law.sigma_c * r2)
      out.failure = Failure::compression;
    else if (s.shear.norm() > law.tau_c * r2)
      out.failure = Failure::shear;
    if (out.failure != Failure::none) {
      s.bonded = false;
      out.failure_normal = fn;
      out.failure_shear = s.shear.norm();
    }
  }
  if (!s.bonded) {
    if (overlap <= 0.0) {  // no tension once unbonded (eq. 2.16)
      s.shear.setZero();
      out.active = false;
      return out;
    }
    const double limit = law.mu * std::abs(fn);  // Coulomb (eqs 2.17-2.18)
    const double fs2 = s.shear.squaredNorm();
    if (fs2 > limit * limit) s.shear *= limit / std::sqrt(fs2);
  }
  out.force = fn * n + s.shear;
  out.torque1 = (-a1 * n).cross(s.shear);
  out.torque2 = (a2 * n).cross(-s.shear);
  return out;
}

// Local non-viscous damping of one component (seed 000 eqs 2.9-2.10):
// -alpha |F| sign(v).
inline double local_damping(double alpha, double f, double v) {
  return v > 0.0 ? -alpha * std::abs(f) : v < 0.0 ? alpha * std::abs(f) : 0.0;
}

// The critical step of a mass-spring pair (eq. 2.19).
inline double critical_step(double mass, double stiffness) { return 2.0 * std::sqrt(mass / stiffness); }

// The densest coordination the automatic step allows for: 12 contacts (a
// monodisperse close packing).
inline constexpr double kPackCoordination = 12.0;

// The critical step of a grain of mass m inside a dense pack. One contact
// between spheres (I = 0.4 m r^2) couples the two grains' translations through
// K_N along the normal (mass-normalised norm 2 K_N / m) and translations and
// rotations through k_S across it (norm (2 + 2 r^2 m / I) k_S / m = 7 k_S / m).
// A grain in Z contacts takes part in Z such terms, so the pack's largest
// eigenvalue is at most Z max(2 K_N, 7 k_S) / m, and the leapfrog is stable
// below 2 / sqrt of that. With K_N = k_S and Z = 12 this is 0.109 of eq. 2.19's
// pair step: seed 000's t_frac = 0.1 sits at the edge, as the gravity pour
// showed (docs/validation.md).
inline double pack_critical_step(double mass, const ContactLaw& law) {
  return 2.0 * std::sqrt(mass / (kPackCoordination * std::max(2.0 * law.kn, 7.0 * law.ks)));
}

// The automatic step (particles.time_step: auto): t_frac of the pair step of
// eq. 2.20, and no more than half the dense pack's critical step.
inline double automatic_step(double mass, const ContactLaw& law, double t_frac) {
  return std::min(t_frac * critical_step(mass, std::max(law.kn, law.ks)), 0.5 * pack_critical_step(mass, law));
}

// A fixed step (not auto) checked again as grains crush (seed 000 §2.2.2:
// lighter, so their critical step of eq. 2.19 shortens): past it the run
// stops here with a message, not later on non-finite positions.
inline void check_fixed_step(double h, double lightest, const ContactLaw& law) {
  const double crit = critical_step(lightest, std::max(law.kn, law.ks));
  if (h > crit)
    throw std::runtime_error(
        fmt::format("the particle step {:.4g} s (particles.time_step) now exceeds the critical step {:.4g} s "
                    "(seed 000 eq. 2.19) of the lightest grain, crushed to {:.4g} kg: use time_step: auto, "
                    "which splits the step as grains crush",
                    h, crit, lightest));
}

// Equal parts of h, each no longer than `stable` (1e-9 of slack: a step that
// is the stable one up to round-off is not split). A stable step that makes
// more than a run counts (coupler::kMostWindows, 1e15: past it the run would
// not end and the count would overflow a long; or is zero or NaN) stops the run with a
// message; `cause` says what shortened it.
inline long split_for(
    double h, double stable,
    const char* cause =
        "a grain has become too light for the contact stiffness (seed 000 "
        "eq. 2.19): check the crushing parameters (particles.contact.bond.crush_fraction)") {
  const double n = std::ceil(h / stable - 1e-9);
  if (!(n <= coupler::kMostWindows))
    throw std::runtime_error(
        fmt::format("the automatic particle step fell to {:.4g} s, {:.3g} sub-steps of the "
                    "{:.4g} s step, more than a run can count: {}",
                    stable, n, h, cause));
  return std::max(1L, static_cast<long>(n));
}

}  // namespace coflow::particles::dem
