#include "fluid/fv/refinement_params.hpp"

#include <fmt/format.h>

#include <cmath>
#include <functional>

namespace coflow::fluid::fv {

namespace {

// A criterion on a value's size per cell (`kind`: vorticity, k).
std::function<void(config::Visitor&)> magnitude(std::vector<RefinementCriterion>& out, const char* kind,
                                                const char* refine_doc, const char* coarsen_doc) {
  return [&out, kind, refine_doc, coarsen_doc](config::Visitor& s) {
    auto& c = out.emplace_back();
    c.kind = kind;
    s.required("refine_above", c.refine_above, refine_doc, config::greater(0.0));
    s.required("coarsen_below", c.coarsen_below, coarsen_doc, config::at_least(0.0));
    if (s.reading() && c.coarsen_below >= c.refine_above)
      s.fail("coarsen_below", fmt::format("{} is not below refine_above ({}): leaves would refine and "
                                          "coarsen back at every regrid",
                                          c.coarsen_below, c.refine_above));
  };
}

void visit_criteria(config::Visitor& v, std::vector<RefinementCriterion>& out) {
  v.choices(
      "criteria",
      "where the grid refines: a leaf refines where any criterion asks and coarsens where all allow (seed "
      "003 "
      "§4.1.1: vorticity, turbulence, walls, particles)",
      {{"vorticity", "by the vorticity's magnitude |omega| in a cell (seed 003 Fig. 1.4)",
        magnitude(out, "vorticity", "1/s: a leaf refines where a cell's |omega| exceeds it",
                  "1/s: a leaf may coarsen where all its cells are below it (less than refine_above)")},
       {"k", "by the turbulence kinetic energy k in a cell (fluid.turbulence on)",
        magnitude(out, "k", "m^2/s^2: a leaf refines where a cell's k exceeds it",
                  "m^2/s^2: a leaf may coarsen where all its cells are below it (less than refine_above)")},
       {"walls", "near the non-periodic faces of the box",
        [&](config::Visitor& s) {
          auto& c = out.emplace_back();
          c.kind = "walls";
          s.required("distance", c.distance, "m: leaves within it of a wall (or any domain face) refine",
                     config::greater(0.0));
        }},
       {"box", "inside an axis-aligned box",
        [&](config::Visitor& s) {
          auto& c = out.emplace_back();
          c.kind = "box";
          s.required("lower", c.lower, "[x, y, z], m");
          s.required("upper", c.upper, "[x, y, z], m");
          if (!s.reading()) return;
          for (const char* key : {"lower", "upper"})
            if ((key[0] == 'l' ? c.lower : c.upper).values.size() != 3)
              s.fail(key, "needs 3 numbers [x, y, z]");
          if (c.lower.values.size() == 3 && c.upper.values.size() == 3)
            for (std::size_t d = 0; d < 3; ++d)
              if (c.upper.values[d] <= c.lower.values[d])
                s.fail("upper", fmt::format("upper[{}] = {} is not above lower[{}] = {}", d, c.upper.values[d], d,
                                            c.lower.values[d]));
        }},
       {"bodies",
        "around immersed boundaries (immersed.method ibm): leaves within 2.5 finest cells of a marker refine "
        "to "
        "the finest level, where the forcing runs",
        [&](config::Visitor&) { out.emplace_back().kind = "bodies"; }},
       {"particles",
        "where point particles are: the cells their momentum source reaches (immersed.method point)",
        [&](config::Visitor&) { out.emplace_back().kind = "particles"; }}});
}

}  // namespace

void RefinementParams::visit(config::Visitor& v) {
  v("levels", levels,
    "levels of the grid, the finest being domain.cells (each coarser one halves the cells per axis); 1: the "
    "composite machinery on one level",
    config::in_range(1, 8));
  v("patch", patch, "cells per edge of each leaf's patch (even, at least 4): the blocks of the block-structured grid",
    config::Rule{"even, 4 to 64", [](const config::ValueRef& r) {
                   const int n = *std::get<int*>(r);
                   return n >= 4 && n <= 64 && n % 2 == 0 ? std::string()
                                                          : fmt::format("must be even and in 4 .. 64 (got {})", n);
                 }});
  v("every", every, "steps between regrids (criteria, p4est adapt, balance and repartition, conservative transfer)",
    config::greater(0.0));
  v("diffusion", diffusion,
    "explicit: Heun's step, held to h^2 / (4 d nu) on the finest cells; implicit: the same step with "
    "backward Euler in its predictor and Crank-Nicolson in its corrector for the viscous term, in "
    "incremental pressure-correction form (non-incremental with immersed boundaries; a Helmholtz system "
    "per velocity component, GMRES + BoomerAMG), held to the advective limit alone",
    config::one_of({"explicit", "implicit"}));
  visit_criteria(v, criteria);
}

long RefinementParams::base_cells(const config::Config& cfg, int axis) const {
  return cfg.domain.cells[axis] >> (levels - 1);
}

void RefinementParams::check(config::Visitor& v, const config::Config& cfg) const {
  const auto& d = cfg.domain;
  const int dims = d.cells[2] == 1 ? 2 : 3;
  // levels or patch out of range is reported by visit(); checked against
  // them, the grid would only get a second, misleading message.
  if (levels < 1 || levels > 8 || patch < 4 || patch > 64 || patch % 2 != 0) return;
  const long block = static_cast<long>(patch) << (levels - 1);
  for (int a = 0; a < dims; ++a)
    if (d.cells[a] % block != 0) {
      const long below = d.cells[a] / block * block, above = below + block;
      v.fail(
          "refinement.levels",
          fmt::format(
              "domain.cells[{}] = {} is not a multiple of patch x 2^(levels - 1) = {}: the finest level must "
              "cut into whole patches of the base level; use {} cells, or fewer levels or a smaller patch",
              a, d.cells[a], block,
              below > 0 ? fmt::format("{} or {}", below, above) : std::to_string(above)));
      return;
    }
  const auto h = d.spacing();
  for (int a = 1; a < dims; ++a)
    if (std::abs(h[a] - h[0]) > 1e-9 * h[0]) {
      v.fail("refinement.levels", fmt::format("the cells are {:.6g} x {:.6g}{}: the adaptive grid's cells are cubes (p4est's "
                                   "trees): make (upper - lower) / cells the same along every axis",
                                   h[0], h[1], dims == 3 ? fmt::format(" x {:.6g}", h[2]) : std::string()));
      return;
    }
  if (criteria.empty())
    v.fail("refinement.criteria",
           "give at least one criterion (vorticity, k, walls, box, bodies or particles)");
}

}  // namespace coflow::fluid::fv
