// fluid.fv: parameters shared by the fv and fv-reference variants (seed 003
// §4.1: finite volumes on a staggered grid, Chorin's projection, IMEX steps).
#pragma once

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <string>

#include "coflow/config.hpp"
#include "coflow/run_config.hpp"
#include "fluid/fv/refinement_params.hpp"

namespace coflow::fluid::fv {

struct FvParams {
  std::string advection = "upwind";
  std::string form = "divergent";
  std::string time = "sbdf2";
  double cfl = 0.5;
  double max_step = 0.0;
  double tolerance = 1e-10;
  int max_iterations = 200;
  std::string multigrid = "geometric";
  RefinementParams refinement;
  void visit(config::Visitor& v) {
    v("advection", advection,
      "central (second order) or upwind (second-order upwind-biased, bounded by van Leer's limiter: no new "
      "extrema)",
      config::one_of({"central", "upwind"}));
    v("form", form, "advection term: divergent div(u u) or non-divergent (u . grad) u (seed 003 §4.1)",
      config::one_of({"divergent", "non-divergent"}));
    v("time", time,
      "IMEX scheme, advection explicit and diffusion implicit, with a variable step: sbdf2 (Ascher, Ruuth & "
      "Wetton 1995; Wang & Ruuth 2008) or cnab2 (Crank-Nicolson / Adams-Bashforth); the first step by the "
      "first-order member (IMEX Euler)",
      config::one_of({"sbdf2", "cnab2"}));
    v("cfl", cfl, "Courant number C of the variable step (seed 003 eq. 4.1): dt = C / sum_d(max|u_d| / dx_d)",
      config::greater(0.0));
    v("max_step", max_step, "s: the largest step (0: no limit but the coupling window)",
      config::at_least(0.0));
    v("tolerance", tolerance,
      "relative residual (2-norm) at which the pressure Poisson and the implicit viscous solves stop",
      config::greater(0.0));
    v("max_iterations", max_iterations, "iterations of one linear solve before the run stops with a message",
      config::greater(0.0));
    v("multigrid", multigrid,
      "fv: the preconditioner of the conjugate gradients. geometric: the pressure Poisson by coflow's "
      "matrix-free geometric multigrid (full coarsening, red-black Gauss-Seidel, trilinear transfers; "
      "fluid/fv/poisson_multigrid.hpp) where every rank's block has an even number of cells along each axis "
      "and the cells' aspect ratio is at most 2, else by pfmg, and the viscous solves by pfmg (by a diagonal "
      "preconditioner where their matrix is strongly diagonally dominant: a short step); pfmg: hypre's "
      "Struct semicoarsening multigrid (Ashby & "
      "Falgout 1996) for all; smg: hypre's SMG (Schaffer 1998; more robust on stretched cells, slower; a "
      "periodic axis needs a power of two "
      "cells)",
      config::one_of({"geometric", "pfmg", "smg"}));
    v.section(
        "refinement",
        "fv on a block-structured adaptive grid (seed 003 §4.1.1; p4est): levels of ratio 2 in patches of "
        "cells, refined and coarsened by the criteria every few steps. There the steps are Heun's "
        "second-order Runge-Kutta with central fluxes through the composite faces, diffusion explicit or "
        "implicit (refinement.diffusion; advection, form, time and multigrid are not used; the step is also "
        "kept below (16 nu h^2 / U^4)^(1/3) on the finest cells, Heun's limit for central advection, "
        "and with explicit diffusion below h^2 / (4 d nu)), projected at each stage with hypre's GMRES + "
        "BoomerAMG to the relative residual tolerance (at most max_iterations); "
        "outflow and pressure faces are both p = 0 with du/dn = 0 (not fv's convective outflow)",
        [&](config::Visitor& s) {
          if (s.reading() && !refinement.on) return;
          refinement.visit(s);
        },
        &refinement.on);
  }
  void check(config::Visitor& v, const config::Config& cfg) const {
    const auto& d = cfg.domain;
    if (d.cells[0] == 1 || d.cells[1] == 1)
      v.fail("", "the fv fluid is 2D in x-y or 3D: domain.cells[0] and [1] must be more than 1");
    if (cfl > 1.0)
      v.fail("cfl",
             fmt::format("{} > 1: the explicit advection is unstable beyond C = 1; use 0.2 to 0.8", cfl));
    if (refinement.on) refinement.check(v, cfg);
    if (multigrid == "smg" && !refinement.on)
      for (int a = 0; a < 3; ++a) {
        const long n = d.cells[static_cast<std::size_t>(a)];
        if (n > 1 && d.periodic[static_cast<std::size_t>(a)] && (n & (n - 1)) != 0)
          v.fail(
              "multigrid",
              fmt::format("smg with {} cells along the periodic axis {}: hypre's SMG preconditioner breaks "
                          "down unless a periodic axis has a power of two cells (measured: 20, 24, 40 and 48 "
                          "fail, 16, 32 and 64 converge); use pfmg or geometric, or {} or {} cells",
                          n, "xyz"[a], std::bit_floor(static_cast<unsigned long>(n)),
                          std::bit_ceil(static_cast<unsigned long>(n))));
      }
  }
};

}  // namespace coflow::fluid::fv
