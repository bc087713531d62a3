// coflow-check: metrics of a finished run against analytic solutions and
// published data, printed as `name=value` lines for tests/validation/validate.sh.
//
//   coflow-check profile RUN_DIR   steady channel/duct/Couette profile: l2_error
//   coflow-check decay RUN_DIR     Taylor-Green energy decay rate: decay_rate_error
//   coflow-check mass RUN_DIR      relative mass drift over the run: mass_drift
//   coflow-check compare RUN_A RUN_B   last snapshots: max_difference (relative)
//   coflow-check impact RUN_DIR    two-sphere impact: duration_error, restitution, energy_error
//   coflow-check pour RUN_DIR      gravity pour: kinetic_energy_ratio, packing_fraction
//   ... and the modes listed below (one per validation family).
//
// The physical parameters come from the run's resolved config.yaml.
#include "check.hpp"

using namespace coflow::check;

int main(int argc, char** argv) {
  try {
    const std::string what = argc > 1 ? argv[1] : "";
    // Every argument after the mode is a run directory with its resolved
    // configuration (a missing one would reach the readers below).
    for (int a = 2; a < argc; ++a)
      if (!std::ifstream(std::string(argv[a]) + "/config.yaml"))
        throw std::runtime_error(std::string(argv[a]) + " is not a run directory (no config.yaml in it)");
    if (what == "profile" && argc == 3) return profile(argv[2]);
    if (what == "dfg_cylinder" && argc == 3) return dfg_cylinder(argv[2]);
    if (what == "dfg_cylinder_unsteady" && argc == 3) return dfg_cylinder_unsteady(argv[2]);
    if (what == "solid_channel" && argc == 3) return solid_channel(argv[2]);
    if (what == "uniform_stream" && argc == 3) return uniform_stream(argv[2]);
    if (what == "inlet_profile" && argc == 3) return inlet_profile(argv[2]);
    if (what == "probes" && argc == 3) return probes(argv[2]);
    if (what == "hydrostatic" && argc == 3) return hydrostatic(argv[2]);
    if (what == "fluid_walls" && argc == 3) return fluid_walls(argv[2]);
    if (what == "walls_pressure_drop" && argc == 3) return walls_pressure_drop(argv[2]);
    if (what == "channel" && argc == 3) return channel(argv[2]);
    if (what == "decay" && argc == 3) return decay(argv[2]);
    if (what == "mass" && argc == 3) return mass(argv[2]);
    if (what == "ramp" && argc == 3) return ramp(argv[2]);
    if (what == "compare" && argc == 4) return compare(argv[2], argv[3]);
    if (what == "impact" && argc == 3) return impact(argv[2]);
    if (what == "walls" && argc == 3) return walls(argv[2]);
    if (what == "pour" && argc == 3) return pour(argv[2]);
    if (what == "crush" && argc == 3) return crush(argv[2]);
    if (what == "momentum" && argc == 3) return momentum(argv[2]);
    if (what == "drag" && argc == 3) return drag(argv[2]);
    if (what == "buoyancy" && argc == 3) return buoyancy(argv[2]);
    if (what == "settling" && argc == 3) return settling(argv[2]);
    if (what == "dpm_settling" && argc == 3) return dpm_settling(argv[2]);
    if (what == "granular_gas" && argc == 3) return granular_gas(argv[2]);
    if (what == "two_way" && argc == 3) return two_way(argv[2]);
    if (what == "dispersion" && argc == 3) return dispersion(argv[2]);
    if (what == "grid_turbulence" && argc == 3) return grid_turbulence(argv[2]);
    if (what == "grid_turbulence_fv" && argc == 3) return grid_turbulence_fv(argv[2]);
    if (what == "injection" && argc == 3) return injection(argv[2]);
    if (what == "jet" && argc == 3) return jet(argv[2]);
    if (what == "pair_into_mesh" && argc == 3) return pair_into_mesh(argv[2]);
    if (what == "inlet_stream" && argc == 3) return inlet_stream(argv[2]);
    if (what == "inlet_mass" && argc == 3) return inlet_mass(argv[2]);
    if (what == "rotation" && argc == 3) return rotation(argv[2]);
    if (what == "laplace" && argc == 3) return laplace(argv[2]);
    if (what == "contact_angle" && argc == 3) return contact_angle(argv[2]);
    if (what == "layered" && argc == 3) return layered(argv[2]);
    if (what == "colour_mass" && argc == 3) return colour_mass(argv[2]);
    if (what == "permeability" && argc == 3) return permeability(argv[2]);
    if (what == "washburn" && argc == 3) return washburn(argv[2]);
    if (what == "injection_phase" && argc == 3) return injection_phase(argv[2]);
    if (what == "grain_interface" && argc == 3) return grain_interface(argv[2]);
    if (what == "bridge" && argc == 3) return bridge(argv[2]);
    if (what == "cavity" && argc == 3) return cavity(argv[2]);
    if (what == "tg_error" && argc == 3) return tg_error(argv[2]);
    if (what == "stokes_layer" && argc == 3) return stokes_layer(argv[2]);
    if (what == "vortex" && argc == 3) return vortex(argv[2]);
    if (what == "divergence" && argc == 3) return divergence(argv[2]);
    if (what == "outflow_reflection" && argc == 4) return outflow_reflection(argv[2], argv[3]);
    if (what == "ke_decay" && argc == 3) return ke_decay(argv[2]);
    if (what == "ke_grid" && argc == 3) return ke_grid(argv[2]);
    if (what == "ke_grid_levels" && argc == 3) return ke_grid_levels(argv[2]);
    if (what == "ke_channel" && argc == 3) return ke_channel(argv[2]);
    if (what == "ke_backward_step" && argc == 3) return ke_backward_step(argv[2]);
    if (what == "ibm_steady" && argc == 3) return ibm_steady(argv[2]);
    if (what == "ibm_shedding" && argc == 3) return ibm_shedding(argv[2]);
    if (what == "ibm_frames" && argc == 4) return ibm_frames(argv[2], argv[3]);
    if (what == "ibm_extrapolated" && argc == 4) return ibm_extrapolated(argv[2], argv[3]);
    if (what == "ibm_oscillating" && argc == 3) return ibm_oscillating(argv[2]);
    if (what == "ibm_particles" && argc == 3) return ibm_particles(argv[2]);
    if (what == "ibm_balance" && argc == 3) return ibm_balance(argv[2]);
    if (what == "ibm_couette" && argc == 3) return ibm_couette(argv[2]);
    if (what == "ibm_couette_oscillating" && argc == 3) return ibm_couette_oscillating(argv[2]);
    std::fprintf(stderr, "usage: coflow-check profile|decay|mass RUN_DIR | compare RUN_A RUN_B\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "coflow-check: %s\n", e.what());
    return 1;
  }
}
