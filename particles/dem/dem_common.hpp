// Pieces both DEM variants use: parameters, wall geometry, the integration of
// one particle, minimum images.
#pragma once

#include <array>

#include "particles/dem/contact.hpp"
#include "particles/dem/initial.hpp"
#include "particles/particles_interface.hpp"

namespace coflow::particles::dem {

struct DemParams {
  void visit(config::Visitor&) {}  // the dem variants use only the common particle keys
};

// Separation vector a - b with the minimum image on periodic axes.
inline V3 min_image(V3 d, const DemSetup& s) {
  for (int k = 0; k < 3; ++k)
    if (s.periodic[k]) {
      const double L = s.upper[k] - s.lower[k];
      d[k] -= L * std::round(d[k] / L);
    }
  return d;
}

// Inward unit normal and position of a face's plane.
inline V3 face_normal(int f) {
  V3 n = V3::Zero();
  n[f / 2] = f % 2 == 0 ? 1.0 : -1.0;
  return n;
}
inline double face_distance(int f, const V3& x, const DemSetup& s) {
  const int a = f / 2;
  return f % 2 == 0 ? x[a] - s.lower[a] : s.upper[a] - x[a];
}

// Central differences with local damping, seed 000 eqs 2.7-2.8 and 2.5:
// velocities at half steps, positions at whole steps.
inline void integrate(V3& x, V3& v, V3& w, const V3& force, const V3& torque, double m, double I, double alpha,
                      double h) {
  for (int k = 0; k < 3; ++k) {
    v[k] += (force[k] + local_damping(alpha, force[k], v[k])) / m * h;
    w[k] += (torque[k] + local_damping(alpha, torque[k], w[k])) / I * h;
  }
  x += v * h;
}

}  // namespace coflow::particles::dem
