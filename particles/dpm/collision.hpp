// Hard-sphere collisions of point particles (seed 003 §3.2.4-3.2.5, after Crowe
// et al.): the contact time along straight trajectories (eq. 4.28) and the
// velocities after a binary particle-particle (eqs 3.44-3.49) or particle-wall
// (eqs 3.50-3.52) collision. Shared by dpm and dpm-reference.
#pragma once

#include <cmath>
#include <limits>

#include "particles/dem/mesh.hpp"
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
// print a minus sign that belongs to the opposite orientation of n). Returns
// whether an impulse was applied (false: the pair does not approach).
inline bool collide_pair(V3& up, V3& wp, double mp, double Dp, V3& uq, V3& wq, double mq, double Dq, const V3& n,
                         const Restitution& r) {
  const V3 ur = up - uq;                                               // eq. 3.46
  const double un = ur.dot(n);
  if (un <= 0.0) return false;                                         // not approaching
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
  return true;
}

// Velocities after hitting a wall whose unit normal n points from the particle
// into the wall ((u . n) > 0 on approach), eqs 3.50-3.52. Returns whether an
// impulse was applied.
inline bool collide_wall(V3& u, V3& w, double D, const V3& n, const Restitution& r) {
  const double un = u.dot(n);
  if (un <= 0.0) return false;
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
  return true;
}

// Earliest t in [0, dt) at which a sphere of radius R with centre x + u t
// touches the triangle (a, b, c), approaching it; +infinity if none. The
// continuous form of seed 003 Algorithm 2 (eqs 4.32-4.37 intersect the centre's
// path with the triangle's plane): the centre meets the plane offset by R inside
// the triangle (face), a cylinder of radius R about an edge, or a sphere of
// radius R about a vertex; the earliest of these. A sphere that already touches
// and approaches collides at t = 0. `point` is the contact point on the triangle.
inline double sweep_triangle(const V3& x, const V3& u, double R, double dt, const V3& a, const V3& b, const V3& c,
                             V3& point) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  double best = inf;
  auto consider = [&](double t, const V3& p) {
    if (t < best) {
      best = t;
      point = p;
    }
  };
  // Closest point now: already touching?
  {
    bool face = false;
    const V3 p0 = dem::closest_on_triangle(x, a, b, c, face);
    const V3 d = p0 - x;
    if (d.squaredNorm() <= R * R) {
      if (u.dot(d) > 0.0) {
        point = p0;
        return 0.0;
      }
      // touching but moving away or along: later contacts with other parts of
      // the same (planar) triangle cannot happen
      return inf;
    }
  }
  // Face: the plane offset by R on the side the centre is.
  const V3 n = (b - a).cross(c - a).normalized();
  const double s0 = (x - a).dot(n), un = u.dot(n);
  if (s0 * un < 0.0) {
    const double side = s0 > 0.0 ? 1.0 : -1.0;
    const double t = (side * R - s0) / un;
    if (t >= 0.0 && t < dt) {
      const V3 q = x + u * t - side * R * n;  // foot of the centre on the plane
      const V3 v0 = b - a, v1 = c - a, v2 = q - a;
      const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
      const double den = d00 * d11 - d01 * d01;
      const double beta = (d11 * d20 - d01 * d21) / den, gamma = (d00 * d21 - d01 * d20) / den;
      if (beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0) consider(t, q);
    }
  }
  // Smallest root in [0, dt) of A t^2 + 2 B t + C = 0 with C >= 0 (outside now,
  // or touching: t = 0). C < 0 about an edge: the centre is already within R of the edge's line
  // but not of the edge (the check above), beyond one of its ends; it can
  // reach the edge only past that end's vertex, which the vertices' test
  // finds. (Its root here is negative: it once logged an impact 0.056 s
  // before its step, a slow particle beside the plate's corner in the jet.)
  auto first_root = [&](double A, double B, double C) {
    if (A <= 0.0 || B >= 0.0 || C < 0.0) return inf;
    const double disc = B * B - A * C;
    if (disc < 0.0) return inf;
    const double t = C / (-B + std::sqrt(disc));
    return t < dt ? t : inf;
  };
  // Edges: |(x + u t - p) - ((x + u t - p) . e) e| = R, foot within the edge.
  const V3* corners[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    const V3& p = *corners[k];
    const V3& q = *corners[(k + 1) % 3];
    const double L = (q - p).norm();
    const V3 e = (q - p) / L;
    const V3 m = x - p;
    const V3 mp = m - m.dot(e) * e, up = u - u.dot(e) * e;
    const double t = first_root(up.squaredNorm(), mp.dot(up), mp.squaredNorm() - R * R);
    if (t < best) {
      const double along = (m + u * t).dot(e);
      if (along >= 0.0 && along <= L) consider(t, p + along * e);
    }
  }
  // Vertices.
  for (const V3* v : corners) {
    const V3 m = x - *v;
    consider(first_root(u.squaredNorm(), m.dot(u), m.squaredNorm() - R * R), *v);
  }
  return best;
}

}  // namespace coflow::particles::dpm
