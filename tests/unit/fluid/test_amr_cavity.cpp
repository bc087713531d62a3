// The lid-driven cavity at Re 100 on fv's adaptive grid (fluid/fv/amr) with
// walls: 32^2 cells in the middle, 64^2-fine cells along the four walls
// (2 levels), stepped to steady state; the centre-line velocities against
// Ghia, Ghia & Shin 1982 (Tables I and II), independent data. 1 rank.
#include <mpi.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <vector>

#include "../../validation/ghia_1982.hpp"
#include "amr_compare.hpp"
#include "fluid/fv/amr/composite_flow.hpp"

using namespace coflow::fluid::fv::amr;

namespace {

// Velocity component q along the centre line across `axis` (x = 0.5 for
// axis 0: u against y), from the cells beside it, linear between their
// centres and to the walls' values.
double on_centre_line(const CompositeFlow& flow, const Forest& forest, int axis, int q, double s,
                      double wall_lo, double wall_hi) {
  const auto& g = flow.grid();
  const int along = 1 - axis;
  std::map<double, std::pair<double, int>> line;  // position along -> (sum, count)
  for (long c = 0; c < g.local_cells(); ++c) {
    const auto cell = g.local_cell(c);
    const auto x = g.centre(cell);
    const double h = g.spacing(cell.level);
    if (std::fabs(std::fabs(x[axis] - 0.5) - 0.5 * h) > 1e-12) continue;
    auto& e = line[x[along]];
    e.first += forest.data(static_cast<std::size_t>(
        c / g.cells_per_patch()))[static_cast<std::size_t>(c % g.cells_per_patch()) * 3 +
                                  static_cast<std::size_t>(q)];
    ++e.second;
  }
  std::vector<std::pair<double, double>> p{{0.0, wall_lo}};
  for (const auto& [pos, e] : line) p.emplace_back(pos, e.first / e.second);
  p.emplace_back(1.0, wall_hi);
  for (std::size_t i = 1; i < p.size(); ++i)
    if (s <= p[i].first)
      return p[i - 1].second +
             (p[i].second - p[i - 1].second) * (s - p[i - 1].first) / (p[i].first - p[i - 1].first);
  return wall_hi;
}

}  // namespace

TEST_CASE("amr cavity: Re 100 on 2 levels against Ghia, Ghia & Shin 1982", "[.][amr_cavity]") {
  ForestSpec spec;
  spec.dims = 2;
  spec.trees = {4, 4, 1};
  spec.max_level = 1;
  spec.patch = 8;
  spec.components = 3;
  spec.refine = [](int, const Index3& p) {  // the patches along the walls
    return p[0] == 0 || p[0] == 3 || p[1] == 0 || p[1] == 3;
  };
  Forest forest(MPI_COMM_SELF, spec);
  CompositeFlow flow(forest, {{0.0, 0.0, 0.0}, 0.25}, 0.01);
  flow.set_wall_velocity(3, {1.0, 0.0, 0.0});  // the lid, y+
  flow.project_initial();
  const double dt = 0.0045;  // CFL 0.29 on the fine cells; nu dt / h^2 = 0.18
  // To steady state: u at the centre changing by less than 1e-5 U per L/U.
  double change = 1.0, before = 0.0;
  int steps = 0;
  while (steps < 8000 && change > 1e-5) {
    for (int n = 0; n < 100; ++n, ++steps) flow.step(dt);
    const double now = on_centre_line(flow, forest, 0, 0, 0.5, 0.0, 1.0);
    change = std::fabs(now - before) / (100 * dt);
    before = now;
  }
  double worst = 0.0;
  for (const auto& g : coflow::validation::kTableI)
    worst = coflow::test::worst_of(worst,
                                   std::fabs(on_centre_line(flow, forest, 0, 0, g.at, 0.0, 1.0) - g.re100));
  for (const auto& g : coflow::validation::kTableII)
    worst = coflow::test::worst_of(worst,
                                   std::fabs(on_centre_line(flow, forest, 1, 1, g.at, 0.0, 0.0) - g.re100));
  INFO("steps " << steps << " (t = " << steps * dt << "), d u(0.5, 0.5) / dt " << change << ", cells "
                << flow.grid().global_cells() << ", largest deviation from Ghia " << worst);
  CHECK(change <= 1e-5);
  CHECK(worst <= 0.02);  // references.csv: amr_cavity_re100
}
