// The keys common to every fluid variant (fluid.*): material, boundaries,
// initial state. Part of the fluid schema library.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "coflow/config.hpp"
#include "coflow/run_config.hpp"
#include "fluid/profile_expression.hpp"
#include "fluid/turbulence_params.hpp"
#include "fluid/two_phase_params.hpp"

namespace coflow::fluid {

using config::Vec3;

// A velocity face's tabulated profile (profile: table): the factor on the
// face's value at rows of the coordinate along one axis, linear between rows
// and the end rows' factor beyond them.
struct ProfileTable {
  int axis = -1;  // 0, 1, 2; -1: no table
  std::vector<double> at, factor;
  double operator()(double coordinate) const;
};
// Rows "coordinate, factor" (comma or blanks between; '#' starts a comment;
// a line that is not numbers before the first row is a header); throws "what is wrong
// (line N of file)" for a row that is not two numbers, coordinates that do not
// increase, or fewer than two rows.
ProfileTable read_profile_table(const std::string& path, int axis);
// The same with one column per name after the coordinate (rows
// "coordinate, k, epsilon" for names {"k", "epsilon"}): one table per column.
std::vector<ProfileTable> read_profile_columns(const std::string& path, int axis,
                                               const std::vector<std::string>& names);

// One face of the box: x-, x+, y-, y+, z-, z+.
struct BoundaryParams {
  std::string type = "wall";  // wall | pressure | velocity | outflow | symmetry
  config::Numbers value;      // pressure (Pa) or velocity (m/s)
  double ramp = 0.0;          // s: the value rises linearly from zero over this time
  std::string closure = "auto";  // lbm: regularized | zou-he | auto (the type's default)
  std::string phase;             // two-phase: red | blue enters here; "": the colour of the face's cell
  std::string profile = "uniform";  // velocity faces: uniform | parabolic | table | expression
  config::FilePath profile_file;    // table: its rows
  std::string profile_axis = "y";   // table: the axis of its coordinate
  ProfileTable table;               // table: read from profile_file
  std::string profile_expression;   // expression: its text
  ProfileExpression formula;        // expression: parsed from profile_expression
  double k = 0.0, epsilon = 0.0;    // velocity faces with k-epsilon: what enters here (0: turbulence.inlet's)
  double intensity = 0.0, mixing_length = 0.0;  // or k and epsilon from the local inlet speed (0: not)
  config::FilePath turbulence_file;             // or k and epsilon tabulated across the face
  ProfileTable k_table, epsilon_table;          // read from turbulence_file (axis -1: none)
  void visit(config::Visitor& v);
  void check_profile_keys(config::Visitor& v);
  void check_inlet_turbulence_keys(config::Visitor& v);
  // The profile's factor at a point of the face at time t: 1 (uniform), the
  // product over the face's other axes that end in faces (not periodic, more
  // than one cell) of 4 s (1 - s), s the point's fraction of the box along
  // that axis (parabolic), the table at the point's coordinate along its
  // axis, or the expression at the point's coordinates (m; on the face along
  // its normal) and t.
  double profile_factor(int face, const double s[3], const config::Config& cfg, double t = 0.0) const;
};

// The number of fluid steps dt in a coupling window, or 0 when the window is
// not a whole number of them (to 1e-6 of the count): the driver's rule, and
// validate's for lbm's fixed step.
inline long whole_steps(double window, double dt) {
  const double ratio = window / dt;
  return std::abs(ratio - std::round(ratio)) > 1e-6 * ratio ? 0 : std::lround(ratio);
}

inline const std::vector<std::string>& face_names() {
  static const std::vector<std::string> f{"x-", "x+", "y-", "y+", "z-", "z+"};
  return f;
}

// Keys common to every fluid variant.
struct FluidParams {
  double density = 1000.0;
  double viscosity = 1e-6;
  Vec3 body_force{0, 0, 0};
  std::map<std::string, BoundaryParams> boundaries;  // by face; non-periodic faces default to wall
  Vec3 initial_velocity{0, 0, 0};
  double initial_pressure = 0.0;
  std::string initial_field = "uniform";  // uniform | taylor-green
  double initial_amplitude = 0.0;          // taylor-green: U0; vortex: peak swirl, m/s
  config::Numbers initial_center;          // vortex: [x, y], m
  double initial_radius = 0.0;             // vortex: m
  TwoPhaseParams two_phase;                // two_phase.on: the section is given
  TurbulenceParams turbulence;             // turbulence.on: the section is given (fv)
  std::vector<PhaseRegion> initial_phase;  // two-phase: painted regions
  std::vector<SolidParams> solids;         // interior solids
  void visit(config::Visitor& v, const config::Config& cfg);
  void check_solids(config::Visitor& v, const config::Config& cfg) const;
  // Initial velocity (m/s) and pressure (Pa) at a point.
  void initial_state(const config::Config& cfg, const Vec3& x, Vec3& u, double& p) const;
  // The boundary of a face (a wall when not given); periodic faces have type "periodic".
  BoundaryParams boundary(int face, const config::Config& cfg) const;
  // k and epsilon of the fluid entering through each face (x-, x+, y-, ...):
  // a velocity face's own, else turbulence.inlet's; 0 where neither is given.
  // A face with a turbulence intensity I and a mixing length L takes them
  // from the inlet's local speed |u| instead (its k and epsilon here are 0):
  // k = 3/2 (I |u|)^2 (isotropic fluctuations of r.m.s. I |u| per component)
  // and epsilon = C_mu^(3/4) k^(3/2) / L (L a mixing length in Prandtl's
  // sense: with eq. 3.17 it gives nu_t = C_mu^(1/4) k^(1/2) L; not eq. 3.21's
  // l_mu, which would give epsilon = k^(3/2) / L), as OpenFOAM's
  // turbulentIntensityKineticEnergyInlet and
  // turbulentMixingLengthDissipationRateInlet.
  // A face with a turbulence_file takes them from its tables at the point's
  // coordinate along their axis.
  struct FaceTurbulence {
    std::array<double, 6> k{}, epsilon{}, intensity{}, length{};
    std::array<ProfileTable, 6> k_table, epsilon_table;
    double c_mu = 0.09;
    bool from_speed(int f) const { return intensity[static_cast<std::size_t>(f)] > 0.0; }
    bool from_table(int f) const { return k_table[static_cast<std::size_t>(f)].axis >= 0; }
    bool varies(int f) const { return from_speed(f) || from_table(f); }
    // k and epsilon entering through face f at the point x (m) where the
    // inlet's speed is `speed` (m/s; read with an intensity only).
    std::array<double, 2> at(int f, double speed, const double x[3]) const;
  };
  FaceTurbulence inlet_turbulence(const config::Config& cfg) const;
};

}  // namespace coflow::fluid
