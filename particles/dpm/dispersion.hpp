// Turbulent dispersion of point particles: the Langevin model of Sommerfeld
// (2001), seed 003 eqs 3.35-3.42. The fluid velocity a particle sees is the
// interpolated (mean) velocity plus a fluctuation u' that is correlated in time
// (Lagrangian, T_L) and in space (Eulerian, along the particle's slip).
// Random numbers derive from (run.seed, particle id, step, component) only, so
// that dpm, dpm-reference and any rank count draw the same ones.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

#include "particles/dpm/forces.hpp"

namespace coflow::particles::dpm {

struct Dispersion {
  bool on = false;
  double C_T = 0.22;        // eq. 3.38
  std::uint64_t seed = 0;
};

inline std::uint64_t mix(std::uint64_t z) {  // splitmix64 finaliser
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// A standard normal number for (seed, id, step, component), Box-Muller.
inline double gaussian(std::uint64_t seed, std::int64_t id, long step, int component) {
  const std::uint64_t h = mix(mix(mix(seed ^ static_cast<std::uint64_t>(id)) ^ static_cast<std::uint64_t>(step)) ^
                              static_cast<std::uint64_t>(component));
  const double u1 = (static_cast<double>(h >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = (static_cast<double>(mix(h) >> 11) + 0.5) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

// Lagrangian integral time, eq. 3.38 (0 without turbulence).
inline double lagrangian_time(const FluidSample& f, double C_T) {
  return f.k > 0.0 && f.epsilon > 0.0 ? C_T * f.k / f.epsilon : 0.0;
}

// One step dt of the fluctuation u' seen by a particle moving with v (eqs
// 3.35-3.42). A particle meeting turbulence for the first time draws u' from
// the stationary distribution, N(0, 2k/3) per component.
inline void langevin_step(V3& uprime, bool& started, const FluidSample& f, const V3& v, double dt,
                          const Dispersion& d, std::int64_t id, long step) {
  const double TL = lagrangian_time(f, d.C_T);
  if (TL <= 0.0) {
    uprime = V3::Zero();
    started = false;
    return;
  }
  const double sigma = std::sqrt(2.0 / 3.0 * f.k);
  if (!started) {
    for (int c = 0; c < 3; ++c) uprime[c] = sigma * gaussian(d.seed, id, step, 3 + c);
    started = true;
    return;
  }
  const double RL = std::exp(-dt / TL);                     // eq. 3.37
  const double LE = 3.0 * TL * sigma;                       // eq. 3.42
  const V3 dr = (v - (f.u + uprime)) * dt;                  // slip of the particle from its fluid element
  const double r = dr.norm();
  const double fr = std::exp(-r / LE);                      // eq. 3.40
  const double gr = (1.0 - r / (2.0 * LE)) * fr;            // eq. 3.41
  for (int c = 0; c < 3; ++c) {
    const double RE = r > 0.0 ? (fr - gr) * dr[c] * dr[c] / (r * r) + gr : 1.0;  // eq. 3.39
    const double R = RL * RE;                                                    // eq. 3.36
    uprime[c] = R * uprime[c] + sigma * std::sqrt(std::max(0.0, 1.0 - R * R)) * gaussian(d.seed, id, step, c);
  }
}

}  // namespace coflow::particles::dpm
