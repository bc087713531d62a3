// Particle diameters drawn from a species' size distribution, the same way in
// DEM (initial packings) and DPM (inlets).
#pragma once

#include <cmath>
#include <numbers>

#include "coflow/config.hpp"

namespace coflow::particles {

// The largest diameter a log-normal species may draw: mean + 6 standard
// deviations (largest_diameter, the ghost layers and the inlets' reach use it).
inline double lognormal_cutoff(double mean, double std) { return mean + 6.0 * std; }

// The largest diameter a species' distribution gives.
inline double largest_diameter(const config::Distribution& d) {
  switch (d.kind) {
    case config::Distribution::Kind::fixed:
      return d.a;
    case config::Distribution::Kind::uniform:
      return d.b;
    case config::Distribution::Kind::lognormal:
      return lognormal_cutoff(d.a, d.b);
  }
  return d.a;
}

// The volume of a sphere of diameter d.
inline double sphere_volume(double d) {
  return std::numbers::pi * d * d * d / 6.0;
}

// The smallest diameter a species' distribution gives; 0 for a log-normal,
// which has no lower bound.
inline double smallest_diameter(const config::Distribution& d) {
  return d.kind == config::Distribution::Kind::lognormal ? 0.0 : d.a;
}

// A diameter from the log-normal with mean D and standard deviation s
// (sigma^2 = ln(1 + s^2 / D^2), mu = ln D - sigma^2 / 2: seed 003 eqs
// 4.20-4.21, whose sigma formula has its parentheses misplaced), truncated at
// lognormal_cutoff(D, s) by resampling: a draw above it is discarded and drawn
// anew, so the result follows the log-normal density renormalised on
// (0, cutoff] (clamping would instead pile the tail's mass onto the cutoff).
// normal(r) returns the r-th standard normal deviate of this particle.
template <class Normal>
double truncated_lognormal(double D, double s, Normal normal) {
  const double s2 = std::log(1.0 + s * s / (D * D));
  const double mu = std::log(D) - 0.5 * s2, sigma = std::sqrt(s2), cutoff = lognormal_cutoff(D, s);
  for (int r = 0;; ++r) {
    const double d = std::exp(mu + sigma * normal(r));
    if (d <= cutoff) return d;
  }
}

}  // namespace coflow::particles
