#include "fluid/analytic/params.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <string>
#include <vector>

namespace coflow::fluid {

void AnalyticParams::visit(config::Visitor& v) {
  v("field", field, "which flow", config::one_of({"quiescent", "uniform", "poiseuille", "taylor-green", "grid-turbulence"}));
  v("velocity", velocity, "uniform: the velocity, m/s");
  v("k", k, "uniform: turbulent kinetic energy of homogeneous, non-decaying turbulence, m^2/s^2",
    config::non_negative());
  v("epsilon", epsilon, "uniform: its dissipation rate, m^2/s^3 (with k > 0)", config::non_negative());
  v("max_velocity", max_velocity, "poiseuille: centre-line speed; taylor-green: amplitude U0, m/s");
  v("flow_axis", flow_axis, "poiseuille, grid-turbulence: flow direction (0 = x, 1 = y, 2 = z)",
    config::in_range(0, 2));
  v("wall_axis", wall_axis, "poiseuille: wall-normal direction", config::in_range(0, 2));
  v("mean_velocity", mean_velocity, "grid-turbulence: mean speed along flow_axis, m/s", config::positive());
  v("mesh_size", mesh_size, "grid-turbulence: grid mesh size M, m", config::positive());
  v("grid_position", grid_position, "grid-turbulence: coordinate of the grid along flow_axis, m");
  if (v.reading() && (k > 0.0) != (epsilon > 0.0))
    v.fail(k > 0.0 ? "epsilon" : "k", "homogeneous turbulence needs both k and epsilon > 0 (or neither)");
  if (v.reading() && k > 0.0 && field != "uniform") v.fail("k", "k and epsilon are for field: uniform");
  // A key of another field set off its default would be ignored (field
  // quiescent with a velocity gave fluid at rest). Not `given`: the resolved
  // file the components read holds every key.
  const AnalyticParams d;
  const std::pair<const char*, std::vector<std::string>> owners[] = {
      {velocity != d.velocity ? "velocity" : "", {"uniform"}},
      {max_velocity != d.max_velocity ? "max_velocity" : "", {"poiseuille", "taylor-green"}},
      {flow_axis != d.flow_axis ? "flow_axis" : "", {"poiseuille", "grid-turbulence"}},
      {wall_axis != d.wall_axis ? "wall_axis" : "", {"poiseuille"}},
      {mean_velocity != d.mean_velocity ? "mean_velocity" : "", {"grid-turbulence"}},
      {mesh_size != d.mesh_size ? "mesh_size" : "", {"grid-turbulence"}},
      {grid_position != d.grid_position ? "grid_position" : "", {"grid-turbulence"}}};
  for (const auto& [key, fields] : owners)
    if (v.reading() && *key != '\0' && std::find(fields.begin(), fields.end(), field) == fields.end())
      v.fail(key, fmt::format("is for field: {} (this run's field is {}): remove it, or set the field",
                              fmt::join(fields, " or "), field));
  if (v.reading() && field == "poiseuille" && flow_axis == wall_axis)
    v.fail("wall_axis", "must differ from flow_axis");
}

void AnalyticParams::check(config::Visitor& v, const config::Config& cfg) const {
  // The decay laws (seed 003 eqs 5.21-5.22) hold downstream of x/M = 16 only.
  if (field != "grid-turbulence") return;
  const double lo = (cfg.domain.lower[flow_axis] - grid_position) / mesh_size;
  if (lo <= 16.0)
    v.fail("grid_position", fmt::format("the domain starts at x/M = {:.3g} from the grid; the decay laws of "
                                        "grid-turbulence need x/M > 16 everywhere (move grid_position upstream)",
                                        lo));
}

}  // namespace coflow::fluid
