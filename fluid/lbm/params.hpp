// fluid.lbm: parameters shared by the lbm and lbm-reference variants.
#pragma once

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "coflow/config.hpp"
#include "coflow/run_config.hpp"

namespace coflow::fluid::lbm {

struct LbmParams {
  std::string lattice = "D3Q19";
  std::string formulation = "incompressible";
  double tau = 0.8;
  std::string collision = "bgk";
  double magic = 0.1875;
  std::string layout = "auto";
  std::string bounce_back = "halfway";
  void visit(config::Visitor& v) {
    v("lattice", lattice, "velocity set", config::one_of({"D2Q9", "D3Q19"}));
    v("formulation", formulation,
      "standard BGK, or incompressible (He & Luo 1997: the equilibrium's velocity terms take the reference density)",
      config::one_of({"standard", "incompressible"}));
    v("tau", tau, "relaxation time in lattice units; with dx and the viscosity it fixes dt",
      config::greater(0.5));
    v("collision", collision,
      "bgk (one relaxation time, Bhatnagar, Gross & Krook 1954; Qian, d'Humieres & Lallemand 1992) or trt (two relaxation times, Ginzburg 2008)",
      config::one_of({"bgk", "trt"}));
    v("magic", magic,
      "trt: Lambda = (tau - 1/2)(tau_minus - 1/2); 3/16 puts bounce-back walls exactly for Poiseuille",
      config::positive());
    v("layout", layout,
      "lbm: memory layout of the populations. auto: a fixed distance apart (2^25 cells) when a rank's "
      "block fits it, so that the kernels reach them from a few registers; packed: one after another "
      "(the layout of larger blocks; same results)",
      config::one_of({"auto", "packed"}));
    v("bounce_back", bounce_back,
      "at the surfaces of fluid.solids: halfway (the wall half-way between a fluid and a solid cell's "
      "centres: "
      "a curved surface as a staircase) or interpolated (Bouzidi, Firdaouss & Lallemand 2001, linear: the "
      "wall "
      "where the link crosses the sphere, box or mesh; voxel images and the box's walls stay halfway; what a "
      "cell's links bring back short of what left goes into its rest population, colour by colour, so each "
      "colour's mass is kept) or central (the central linear interpolation of Ginzburg, Verhaeghe & "
      "d'Humieres 2008 at the same crossings: with collision: trt its wall does not move with tau, as "
      "halfway's does not, where interpolated's does)",
      config::one_of({"halfway", "interpolated", "central"}));
  }
  // Checks against the rest of the configuration.
  void check(config::Visitor& v, const config::Config& cfg) const {
    const auto& d = cfg.domain;
    const auto h = d.spacing();
    if (lattice == "D2Q9" && d.cells[2] != 1)
      v.fail("lattice", fmt::format("D2Q9 is two-dimensional: set domain.cells[2] = 1 (got {}) or use D3Q19",
                                    d.cells[2]));
    if (lattice == "D3Q19" && d.cells[2] == 1 && !d.periodic[2])
      v.fail("lattice", "D3Q19 with one cell along z needs domain.periodic[2] = true (or use D2Q9)");
    const int dims = d.cells[2] == 1 ? 2 : 3;
    // A 2D run's cells are dx deep (the fluid's mass, momentum and forces
    // count dx^3 a cell).
    if (dims == 2 && std::abs(h[2] - h[0]) > 1e-9 * h[0])
      v.fail("",
             fmt::format("a two-dimensional lattice Boltzmann grid is one cell of dx deep: domain gives dx = "
                         "{:.6g} m and a depth of {:.6g} m; set domain.upper[2] - domain.lower[2] = {:.6g}",
                         h[0], h[2], h[0]));
    for (int a = 0; a < 2; ++a)
      if (d.cells[a] == 1 && !d.periodic[a])
        v.fail("",
               fmt::format("the lattice Boltzmann grid has one cell along {} between two faces that are not "
                           "periodic: give it more cells or make the axis periodic",
                           "xy"[a]));
    for (int a = 1; a < dims; ++a)
      if (std::abs(h[a] - h[0]) > 1e-9 * h[0])
        v.fail("", fmt::format("the lattice Boltzmann grid needs cubic cells: domain gives dx = {:.6g}, "
                               "d{} = {:.6g} m; adjust domain.cells or the box",
                               h[0], "xyz"[a], h[a]));
  }
};

}  // namespace coflow::fluid::lbm
