// fluid.analytic: which prescribed flow, and its parameters.
#pragma once

#include <string>

#include "coflow/config.hpp"
#include "coflow/run_config.hpp"

namespace coflow::fluid {

using config::Vec3;

struct AnalyticParams {
  std::string field = "quiescent";
  Vec3 velocity{0, 0, 0};  // uniform
  double k = 0.0, epsilon = 0.0;  // uniform: homogeneous turbulence
  double max_velocity = 0.0;    // poiseuille: centre-line speed; taylor-green: amplitude
  int flow_axis = 0;            // poiseuille: flow direction
  int wall_axis = 1;            // poiseuille: wall-normal direction
  // grid-turbulence (Snyder & Lumley 1971, seed 003 eqs 5.21-5.23)
  double mean_velocity = 6.55;  // mean speed along flow_axis, m/s
  double mesh_size = 0.0254;    // grid spacing M, m
  double grid_position = 0.0;   // coordinate of the grid along flow_axis, m
  void visit(config::Visitor& v);
  void check(config::Visitor& v, const config::Config& cfg) const;
};

}  // namespace coflow::fluid
