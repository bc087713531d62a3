// SI <-> lattice units. dx comes from the domain; dt from tau and the viscosity,
// nu = c_s^2 (tau - 1/2) dt (seed 000 eq. 2.41, which writes c_s^2/3: a typo;
// this is the standard relation). Lattice density 1 is the fluid density.
#pragma once

#include <cmath>
#include <string>

#include <fmt/format.h>

namespace coflow::fluid::lbm {

// The relaxation time that gives the step dt at this viscosity and grid, the
// inverse of dt = (tau - 1/2) dx^2 / (3 nu); dt <= 0 keeps `tau`.
inline double tau_for_step(double tau, double dt, double dx, double nu) {
  return dt > 0 ? 0.5 + 3.0 * nu * dt / (dx * dx) : tau;
}

struct Units {
  double dx = 1.0;       // m
  double dt = 1.0;       // s
  double rho = 1.0;      // kg/m^3 (lattice density 1)
  double nu = 1.0;       // m^2/s
  double tau = 1.0;

  static Units from(double dx, double nu, double rho, double tau) {
    Units u;
    u.dx = dx;
    u.nu = nu;
    u.rho = rho;
    u.tau = tau;
    u.dt = (tau - 0.5) * dx * dx / (3.0 * nu);
    return u;
  }
  double velocity() const { return dx / dt; }                      // m/s per lattice unit
  double pressure() const { return rho * velocity() * velocity(); }  // Pa per lattice unit
  double force_density() const { return rho * dx / (dt * dt); }     // N/m^3 per lattice unit
  // Lattice density for a pressure (Pa) relative to the reference: p = c_s^2 (rho - 1).
  double lattice_density(double p) const { return 1.0 + p / (pressure() / 3.0); }
  double pressure_of(double lattice_rho) const { return (lattice_rho - 1.0) * pressure() / 3.0; }
  std::string describe() const {
    return fmt::format("lattice units: dx = {:.6g} m, dt = {:.6g} s (tau = {}, nu = {:.6g} m^2/s), "
                       "1 lattice velocity = {:.6g} m/s, 1 lattice pressure = {:.6g} Pa",
                       dx, dt, tau, nu, velocity(), pressure());
  }
};

}  // namespace coflow::fluid::lbm
