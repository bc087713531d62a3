// Hard-sphere collisions of point particles (seed 003 §3.2.4-3.2.5, after Crowe
// et al.): the contact time along straight trajectories (eq. 4.28) and the
// velocities after a binary particle-particle (eqs 3.44-3.49) or particle-wall
// (eqs 3.50-3.52) collision. Shared by dpm and dpm-reference.
#pragma once

#include <cmath>
#include <limits>

#include "particles/dpm/forces.hpp"

namespace coflow::particles::dpm {

// Earliest t in [0, dt) with |d + dv t| = reach (d = x_p - x_q, dv = u_p - u_q),
// eq. 4.28, for a pair that approaches; +infinity if none. A pair that already
// overlaps and approaches collides at t = 0.
inline double contact_time(const V3& d, const V3& dv, double reach, double dt) {
  const double b = d.dot(dv);
  if (b >= 0.0) return std::numeric_limits<double>::infinity();  // separating
  const double a = dv.squaredNorm();
  const double c = d.squaredNorm() - reach * reach;
  if (c <= 0.0) return 0.0;
  const double disc = b * b - a * c;
  if (disc < 0.0) return std::numeric_limits<double>::infinity();  // they pass each other
  const double t = c / (-b + std::sqrt(disc));  // smaller root, written without cancellation
  return t < dt ? t : std::numeric_limits<double>::infinity();
}

struct Restitution {
  double e = 1.0;    // restitution
  double mu = 0.0;   // dynamic friction
};

// Velocities after the collision of p and q (masses m, diameters D). n is the
// unit normal from p to q; then (u_r . n) > 0 while they approach, and the
// seed's slip criterion reads |u_rc,t| > 7/2 mu (1 + e) (u_r . n) (eqs 3.44-3.45
// print a minus sign that belongs to the opposite orientation of n).
inline void collide_pair(V3& up, V3& wp, double mp, double Dp, V3& uq, V3& wq, double mq, double Dq, const V3& n,
                         const Restitution& r) {
  const V3 ur = up - uq;                                               // eq. 3.46
  const double un = ur.dot(n);
  if (un <= 0.0) return;                                               // not approaching
  const V3 urc = ur + 0.5 * Dp * wp.cross(n) + 0.5 * Dq * wq.cross(n);  // eq. 3.47
  const V3 urc_t = urc - urc.dot(n) * n;                               // eq. 3.48
  const double slip = urc_t.norm();
  const double fp = mq / (mp + mq), fq = mp / (mp + mq);
  if (slip > 3.5 * r.mu * (1.0 + r.e) * un) {  // sliding, eq. 3.44
    const V3 t = urc_t / slip;                 // eq. 3.49
    const V3 j = (1.0 + r.e) * un * (r.mu * t + n);
    const V3 nt = n.cross(t);
    up -= fp * j;
    uq += fq * j;
    wp -= 5.0 * r.mu / Dp * fp * (1.0 + r.e) * un * nt;
    wq -= 5.0 * r.mu / Dq * fq * (1.0 + r.e) * un * nt;
  } else {  // sticking, eq. 3.45
    const V3 j = 2.0 / 7.0 * urc_t + (1.0 + r.e) * urc.dot(n) * n;
    const V3 nt = n.cross(urc_t);
    up -= fp * j;
    uq += fq * j;
    wp -= 10.0 / 7.0 / Dp * fp * nt;
    wq -= 10.0 / 7.0 / Dq * fq * nt;
  }
}

// Velocities after hitting a wall whose unit normal n points from the particle
// into the wall ((u . n) > 0 on approach), eqs 3.50-3.52.
inline void collide_wall(V3& u, V3& w, double D, const V3& n, const Restitution& r) {
  const double un = u.dot(n);
  if (un <= 0.0) return;
  const V3 urc = u + 0.5 * D * w.cross(n);  // eq. 3.52
  const V3 urc_t = urc - urc.dot(n) * n;
  const double slip = urc_t.norm();
  if (slip > 3.5 * r.mu * (1.0 + r.e) * un) {  // sliding, eq. 3.50
    const V3 t = urc_t / slip;
    u -= (1.0 + r.e) * un * (r.mu * t + n);
    w -= 5.0 * r.mu / D * (1.0 + r.e) * un * n.cross(t);
  } else {  // sticking, eq. 3.51
    u -= 2.0 / 7.0 * urc_t + (1.0 + r.e) * urc.dot(n) * n;
    w -= 10.0 / 7.0 / D * n.cross(urc_t);
  }
}

}  // namespace coflow::particles::dpm
