// The exact axisymmetric liquid bridge between two equal touching spheres:
// the reference of the capillary-bridge test (tests/validation/two_phase).
//
// A bridge of volume V wets two spheres of radius R that touch, at the
// contact angle theta. Its free surface has a constant mean curvature
// (Young-Laplace: dp = gamma (1/r_2 + 1/r_1)); in a meridian plane, with x
// along the line of centres (the spheres touch at x = 0, one centred at
// x = R) and y the distance from that line, the profile at slope angle psi
// obeys dy/dx = tan(psi), dpsi/dx = 1/y - H / cos(psi), H = dp / gamma (the
// liquid's pressure over the gas's). It is symmetric about x = 0 (the neck,
// psi = 0, radius r_n) and meets the sphere at the filling angle phi, where
// the contact angle gives phi + psi = 90 degrees - theta. Given phi, H is
// found by shooting from the contact line to the neck (psi = 0 there); phi
// by the volume. The force that pulls the spheres together is, at the neck,
// F = 2 pi gamma r_n - pi r_n^2 dp (the gorge method; Fisher 1926).
//
// As V -> 0 this tends to the small-bridge limit 2 pi R gamma cos(theta)
// (Derjaguin's 4 pi R* gamma cos(theta) with R* = R/2; Willett, Adams,
// Johnson & Seville 2000, Langmuir 16 9396); the toroidal approximation
// (the meridian a circle; Fisher 1926, Lian, Thornton & Adams 1993, J.
// Colloid Interface Sci. 161 138) is close to it for small bridges. The unit
// test `capillary bridge theory` checks both. Valid while the meridian is a
// graph over x (|psi| < 90 degrees): theta + phi < 180 degrees and no
// bulge beyond vertical; throws otherwise.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace coflow::check {

struct BridgeShape {
  double filling = 0.0;    // phi, rad
  double neck = 0.0;       // r_n
  double curvature = 0.0;  // H = dp / gamma (negative: the liquid below the gas's pressure)
  double volume = 0.0;     // of the whole bridge
  double force = 0.0;      // F / gamma, attractive
};

namespace bridge_detail {

// The meridian from the contact line at filling angle phi to x = 0, for the
// curvature H: its slope angle and radius there, and the volume of half the
// bridge (the profile's solid of revolution less the sphere's cap). `ok`
// false where the profile turns vertical or reaches the axis first (psi then
// says which way it turned: up, H too large; down, or y at 0, H too small).
struct Shot {
  double psi = 0.0, neck = 0.0, half_volume = 0.0;
  bool ok = true;
};

inline Shot shoot(double R, double theta, double phi, double H) {
  constexpr int steps = 2000;
  const double xc = R * (1.0 - std::cos(phi)), h = -xc / steps;
  double y = R * std::sin(phi), psi = 0.5 * std::numbers::pi - theta - phi, vol = 0.0;
  const auto dy = [](double, double p) { return std::tan(p); };
  const auto dpsi = [H](double yy, double p) { return 1.0 / yy - H / std::cos(p); };
  Shot s;
  for (int n = 0; n < steps; ++n) {  // classical RK4 in x, from x = xc down to 0
    const double k1y = dy(y, psi), k1p = dpsi(y, psi);
    const double k2y = dy(y + 0.5 * h * k1y, psi + 0.5 * h * k1p),
                 k2p = dpsi(y + 0.5 * h * k1y, psi + 0.5 * h * k1p);
    const double k3y = dy(y + 0.5 * h * k2y, psi + 0.5 * h * k2p),
                 k3p = dpsi(y + 0.5 * h * k2y, psi + 0.5 * h * k2p);
    const double k4y = dy(y + h * k3y, psi + h * k3p), k4p = dpsi(y + h * k3y, psi + h * k3p);
    const double y1 = y + h / 6.0 * (k1y + 2.0 * k2y + 2.0 * k3y + k4y);
    const double psi1 = psi + h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
    vol += -h * std::numbers::pi * 0.5 * (y * y + y1 * y1);  // trapezoid: second order, steps are many
    y = y1, psi = psi1;
    if (!(y > 0.0) || !(std::abs(psi) < 0.49 * std::numbers::pi)) {
      s.ok = false;
      s.psi = y > 0.0 && psi > 0.0 ? 1.0 : -1.0;
      return s;
    }
  }
  s.psi = psi, s.neck = y;
  s.half_volume = vol - std::numbers::pi * xc * xc * (3.0 * R - xc) / 3.0;
  return s;
}

// The curvature H at which the meridian from filling angle phi reaches x = 0
// flat (psi = 0): psi there grows with H (a profile that fails has turned
// down, H too small). Bisection over a bracket that grows until it holds.
inline BridgeShape at_filling(double R, double theta, double phi) {
  double lo = -1.0 / R, hi = 1.0 / R;
  const auto above = [&](double H) {  // psi(0) > 0
    return shoot(R, theta, phi, H).psi > 0.0;
  };
  for (int n = 0; above(lo) && n < 60; ++n) lo *= 2.0;
  for (int n = 0; !above(hi) && n < 60; ++n) hi *= 2.0;
  if (above(lo) || !above(hi))
    throw std::runtime_error("capillary bridge: no meridian for this filling angle");
  for (int n = 0; n < 64; ++n) {
    const double mid = 0.5 * (lo + hi);
    (above(mid) ? hi : lo) = mid;
  }
  const double H = 0.5 * (lo + hi);
  const Shot s = shoot(R, theta, phi, H);
  if (!s.ok || std::abs(s.psi) > 1e-6)
    throw std::runtime_error("capillary bridge: the shooting did not close");
  BridgeShape b;
  b.filling = phi, b.neck = s.neck, b.curvature = H, b.volume = 2.0 * s.half_volume;
  b.force = 2.0 * std::numbers::pi * s.neck - std::numbers::pi * s.neck * s.neck * H;
  return b;
}

}  // namespace bridge_detail

// The bridge of volume V between touching spheres of radius R at contact
// angle theta (rad): the filling angle by bisection on the volume, which
// grows with it (from 1e-3 rad to just short of a vertical meridian).
inline BridgeShape capillary_bridge(double R, double theta, double V) {
  double lo = 1e-3, hi = std::min(0.5 * std::numbers::pi, std::numbers::pi - theta) - 1e-3;
  if (bridge_detail::at_filling(R, theta, lo).volume > V ||
      bridge_detail::at_filling(R, theta, hi).volume < V)
    throw std::runtime_error("capillary bridge: the volume is outside the shapes this solves");
  for (int n = 0; n < 40; ++n) {
    const double mid = 0.5 * (lo + hi);
    (bridge_detail::at_filling(R, theta, mid).volume < V ? lo : hi) = mid;
  }
  return bridge_detail::at_filling(R, theta, 0.5 * (lo + hi));
}

// The toroidal approximation at filling angle phi (the meridian a circle of
// radius r_1 meeting the sphere at theta; Lian et al. 1993 eqs. for zero
// separation): r_1 = R (1 - cos phi) / cos(phi + theta), r_2 = R sin phi -
// r_1 (1 - sin(phi + theta)), F / gamma = pi r_2 (1 + r_2 / r_1) at the neck.
inline double toroidal_force(double R, double theta, double phi) {
  const double r1 = R * (1.0 - std::cos(phi)) / std::cos(phi + theta);
  const double r2 = R * std::sin(phi) - r1 * (1.0 - std::sin(phi + theta));
  return std::numbers::pi * r2 * (1.0 + r2 / r1);
}

}  // namespace coflow::check
