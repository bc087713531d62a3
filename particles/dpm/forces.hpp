// Point-particle (DPM) force laws of seed 003 §2.4 and §3.2.1: the fluid at the
// particle, the coefficients and the rates of eqs 3.28-3.30. Shared by dpm and
// dpm-reference; unit-tested against hand-computed values.
#pragma once

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

namespace coflow::particles::dpm {

using V3 = Eigen::Vector3d;

// The fluid at a particle's position: velocity, vorticity (curl u), turbulent
// kinetic energy and dissipation, density and dynamic viscosity.
struct FluidSample {
  V3 u = V3::Zero();
  V3 vorticity = V3::Zero();
  double k = 0.0, epsilon = 0.0;
  double rho = 0.0, mu = 0.0;
};

// A sample from its 10 doubles: u, vorticity, k, epsilon, rho, mu.
inline FluidSample fluid_sample(const double* s) {
  return {V3(s), V3(s + 3), s[6], s[7], s[8], s[9]};
}

// Which terms of eq. 3.29 / 3.30 act (particles.forces).
struct ForceSet {
  bool gravity_buoyancy = true;
  bool drag = true;
  bool saffman_lift = true;
  bool magnus_lift = true;
  bool torque = true;
};

// Schiller & Naumann, eq. 3.31, as the correction f = C_d Re_p / 24 to Stokes
// drag (finite at Re_p = 0): 1 + 0.15 Re^0.687 up to Re_p = 1000, then C_d = 0.44.
inline double drag_correction(double re_p) {
  return re_p <= 1000.0 ? 1.0 + 0.15 * std::pow(re_p, 0.687) : 0.44 * re_p / 24.0;
}
inline double drag_coefficient(double re_p) { return 24.0 / re_p * drag_correction(re_p); }  // eq. 3.31
// d(f Re_p) / dRe_p: the drag's linear rate (its Jacobian with respect to the
// slip) in units of 1 / tau_p; 1 in Stokes flow, 30 at Re_p 1000.
inline double drag_rate(double re_p) {
  return re_p <= 1000.0 ? 1.0 + 0.15 * 1.687 * std::pow(re_p, 0.687) : 2.0 * 0.44 * re_p / 24.0;
}

// Saffman lift with Mei's correction, eq. 3.32; beta = Re_s / (2 Re_p).
inline double saffman_coefficient(double re_p, double re_s) {
  const double sb = std::sqrt(0.5 * re_s / re_p);
  const double f = re_p <= 40.0 ? (1.0 - 0.3314 * sb) * std::exp(-0.1 * re_p) + 0.3314 * sb
                                 : 0.0524 * std::sqrt(0.5 * re_s);  // (beta Re_p)^0.5 = (Re_s / 2)^0.5
  return 4.1126 / std::sqrt(re_s) * f;
}

// Magnus lift of Oesterle & Dinh, eq. 3.33; gamma = Re_r / (2 Re_p).
inline double magnus_coefficient(double re_p, double re_r) {
  const double gamma = 0.5 * re_r / re_p;
  return 0.45 + (2.0 * gamma - 0.45) * std::exp(-0.075 * std::pow(gamma, 0.4) * std::pow(re_p, 0.7));
}

// Rotational coefficient of Dennis et al., eq. 3.34 (64 pi / Re_r is the Stokes
// torque pi mu D^3 Omega of eq. 2.32); the second branch also beyond Re_r 1000.
inline double rotation_coefficient(double re_r) {
  return re_r <= 32.0 ? 64.0 * std::numbers::pi / re_r : 12.9 / std::sqrt(re_r) + 128.4 / re_r;
}

// The forces (N) and the torque (N m) of the fluid on a particle of diameter D
// and density rho_p moving with v and spinning with w, eqs 3.29-3.30 times m_p
// and I_p. Lift terms use the prefactor pi rho D^n / 8 of eq. 3.29 (eqs 2.22 and
// 2.24 print pi / 24, which does not match Sommerfeld's form they cite).
// Correlations used beyond the range their authors fitted them on (FluidLoad::beyond):
// Mei 1992's Saffman correction for 0.005 <= beta <= 0.4; Oesterle & Dinh
// 1998's Magnus coefficient up to Re_p 140; Dennis et al. 1980's rotational
// coefficient up to Re_r 1000.
enum Beyond : unsigned { kSaffmanBeta = 1u, kMagnusReP = 2u, kRotationReR = 4u };

struct FluidLoad {
  V3 drag = V3::Zero(), saffman = V3::Zero(), magnus = V3::Zero();
  V3 torque = V3::Zero();
  unsigned beyond = 0;  // Beyond flags of the terms that acted outside their range
  V3 force() const { return drag + saffman + magnus; }
};

inline FluidLoad fluid_load(const FluidSample& f, double D, const V3& v, const V3& w, const ForceSet& on) {
  FluidLoad L;
  if (f.mu <= 0.0 || f.rho <= 0.0) return L;  // no fluid
  const V3 rel = f.u - v;
  const double speed = rel.norm();
  const double re_p = f.rho * D * speed / f.mu;  // eq. 2.15
  if (on.drag)  // 3 pi mu D f (u - v) = pi rho D^2 C_d |u - v| (u - v) / 8
    L.drag = 3.0 * std::numbers::pi * f.mu * D * drag_correction(re_p) * rel;
  const double wf = f.vorticity.norm();
  if (on.saffman_lift && wf > 0.0 && re_p > 0.0) {
    const double re_s = f.rho * D * D * wf / f.mu;  // eq. 2.21
    L.saffman = std::numbers::pi * f.rho * D * D * D / 8.0 * saffman_coefficient(re_p, re_s) * rel.cross(f.vorticity);
    const double beta = 0.5 * re_s / re_p;
    if (beta < 0.005 || beta > 0.4) L.beyond |= kSaffmanBeta;
  }
  const V3 omega = 0.5 * f.vorticity - w;  // rotation relative to the fluid
  const double om = omega.norm();
  const double re_r = f.rho * D * D * om / f.mu;  // eq. 2.26
  if (on.magnus_lift && om > 0.0 && re_p > 0.0) {
    L.magnus = std::numbers::pi * f.rho * D * D / 8.0 * magnus_coefficient(re_p, re_r) * speed * omega.cross(rel) / om;
    if (re_p > 140.0) L.beyond |= kMagnusReP;
  }
  if (on.torque && om > 0.0) {  // eq. 2.33
    L.torque = 0.5 * f.rho * std::pow(0.5 * D, 5) * rotation_coefficient(re_r) * om * omega;
    if (re_r > 1000.0) L.beyond |= kRotationReR;
  }
  return L;
}

// Gravity and buoyancy, eq. 2.12: m g (1 - rho / rho_p).
inline V3 gravity_buoyancy(double m, double rho_p, double rho, const V3& g) { return m * (1.0 - rho / rho_p) * g; }

// Particle response time, eq. 2.17.
inline double response_time(double rho_p, double D, double mu) { return rho_p * D * D / (18.0 * mu); }

}  // namespace coflow::particles::dpm
