// Walled flows on fv's adaptive grid (fluid/fv/amr). The lid-driven cavity
// at Re 100: 32^2 cells in the middle, 64^2-fine cells along the four walls
// (2 levels), stepped to steady state with the viscous terms explicit and
// implicit (at 2.6 times the explicit limit); the centre-line velocities against
// Ghia, Ghia & Shin 1982 (Tables I and II), independent data; 1 rank (their
// own ctests, unit.amr_cavity and unit.amr_cavity_implicit). Poiseuille flow from an inlet to an outlet
// with finer cells along the walls, against the exact solution (unit and
// unit.mpi).
#include <mpi.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <vector>

#include "../../validation/ghia_1982.hpp"
#include "amr_testing.hpp"
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

struct CavityResult {
  double change = 1.0;  // |d u(0.5, 0.5) / dt| at the end
  double worst = 0.0;   // largest deviation from Ghia et al.'s Tables I and II
  int steps = 0;
  long cells = 0;
};

// The cavity stepped at dt to steady state: u at the centre changing by less
// than 1e-5 U per L/U.
CavityResult cavity_re100(double dt, bool implicit) {
  auto spec = coflow::test::forest_2d({4, 4, 1}, {false, false, false}, 1, 8, 3);
  spec.refine = [](int, const Index3& p) {  // the patches along the walls
    return p[0] == 0 || p[0] == 3 || p[1] == 0 || p[1] == 3;
  };
  Forest forest(MPI_COMM_SELF, spec);
  CompositeFlow flow(forest, {{0.0, 0.0, 0.0}, 0.25}, 0.01);
  flow.set_wall_velocity(3, {1.0, 0.0, 0.0});  // the lid, y+
  flow.set_implicit_diffusion(implicit);
  flow.project_initial();
  CavityResult r;
  double before = 0.0;
  const int most = static_cast<int>(36.0 / dt);
  while (r.steps < most && r.change > 1e-5) {
    for (int n = 0; n < 100; ++n, ++r.steps) flow.step(dt);
    const double now = on_centre_line(flow, forest, 0, 0, 0.5, 0.0, 1.0);
    r.change = std::fabs(now - before) / (100 * dt);
    before = now;
  }
  for (const auto& g : coflow::validation::kTableI)
    r.worst = coflow::test::worst_of(r.worst,
                                     std::fabs(on_centre_line(flow, forest, 0, 0, g.at, 0.0, 1.0) - g.re100));
  for (const auto& g : coflow::validation::kTableII)
    r.worst = coflow::test::worst_of(r.worst,
                                     std::fabs(on_centre_line(flow, forest, 1, 1, g.at, 0.0, 0.0) - g.re100));
  r.cells = flow.grid().global_cells();
  return r;
}

}  // namespace

TEST_CASE("amr cavity: Re 100 on 2 levels against Ghia, Ghia & Shin 1982", "[.][amr_cavity]") {
  const double dt = 0.0045;  // CFL 0.29 on the fine cells; nu dt / h^2 = 0.18
  const CavityResult r = cavity_re100(dt, false);
  INFO("steps " << r.steps << " (t = " << r.steps * dt << "), d u(0.5, 0.5) / dt " << r.change << ", cells "
                << r.cells << ", largest deviation from Ghia " << r.worst);
  CHECK(r.change <= 1e-5);
  CHECK(r.worst <= 0.02);  // references.csv: amr_cavity_re100
}

TEST_CASE("amr cavity: Re 100 with implicit diffusion past the explicit limit", "[.][amr_cavity_implicit]") {
  // dt 0.016: nu dt / h^2 = 0.66 on the fine cells, 2.6 times the explicit
  // stability limit 1/4 (2D); CFL 1.0 at the lid. The moving lid is a
  // Dirichlet condition of the Helmholtz system for u.
  const double dt = 0.016;
  const CavityResult r = cavity_re100(dt, true);
  INFO("steps " << r.steps << " (t = " << r.steps * dt << "), d u(0.5, 0.5) / dt " << r.change << ", cells "
                << r.cells << ", largest deviation from Ghia " << r.worst);
  CHECK(r.change <= 1e-5);
  CHECK(r.worst <= 0.02);  // references.csv: amr_cavity_re100_implicit
}

namespace {

// Plane Poiseuille flow u = 6 y (1 - y) (U = 1, H = 1).
std::array<double, 3> poiseuille(const std::array<double, 3>& x) { return {6 * x[1] * (1 - x[1]), 0, 0}; }

struct ChannelErrors {
  double u = 0.0, v = 0.0;  // largest |u - u_exact| and |v|
  double dpdx = 0.0;        // by least squares over the cells with 0.5 < x < 1.5
};

// Over all ranks.
ChannelErrors channel_errors(const Forest& forest, const CompositeGrid& g) {
  ChannelErrors e;
  double s[5] = {0, 0, 0, 0, 0};  // n, sx, sp, sxx, sxp
  for (long c = 0; c < g.local_cells(); ++c) {
    const auto x = g.centre(g.local_cell(c));
    const auto v = forest.data(static_cast<std::size_t>(c / g.cells_per_patch()));
    const auto k = static_cast<std::size_t>(c % g.cells_per_patch()) * 3;
    e.u = coflow::test::worst_of(e.u, std::fabs(v[k] - poiseuille(x)[0]));
    e.v = coflow::test::worst_of(e.v, std::fabs(v[k + 1]));
    if (x[0] > 0.5 && x[0] < 1.5) {
      const double terms[5] = {1.0, x[0], v[k + 2], x[0] * x[0], x[0] * v[k + 2]};
      for (int i = 0; i < 5; ++i) s[i] += terms[i];
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, &e.u, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &e.v, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, s, 5, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  e.dpdx = (s[0] * s[4] - s[1] * s[2]) / (s[0] * s[3] - s[1] * s[1]);
  return e;
}

// Inlet x- with the exact profile, outlet x+, started from the exact
// solution and stepped to t = 1 (500 steps of 0.002, or `steps` of 1 / steps).
ChannelErrors run_channel(Forest& forest, CompositeFlow& flow, int steps = 500) {
  flow.set_inlet(0, poiseuille);
  flow.set_outlet(1);
  const auto& g = flow.grid();
  for (long c = 0; c < g.local_cells(); ++c)
    forest.data(static_cast<std::size_t>(
        c / g.cells_per_patch()))[static_cast<std::size_t>(c % g.cells_per_patch()) * 3] =
        poiseuille(g.centre(g.local_cell(c)))[0];
  flow.project_initial();
  for (int n = 0; n < steps; ++n) flow.step(1.0 / steps);
  return channel_errors(forest, g);
}

}  // namespace

TEST_CASE("amr channel: Poiseuille flow from an inlet to an outlet across levels", "[amr][mpi]") {
  // [0, 2] x [0, 1], 8 x 4 trees of 0.25 with 4^2-cell patches; the trees
  // along both walls one level finer. Inlet x- with the exact profile u =
  // 6 U y (1 - y) (U = 1), outlet x+, walls y-, y+; nu 0.1 (Re 10). Started
  // from the exact solution (the dp/dx of Poiseuille: -12 nu U / H^2), it
  // must stay there, up to the discrete steady state's O(h^2).
  auto spec = coflow::test::forest_2d({8, 4, 1}, {false, false, false}, 1, 4, 3);
  spec.refine = [](int, const Index3& p) { return p[1] == 0 || p[1] == 3; };
  Forest forest(MPI_COMM_WORLD, spec);
  CompositeFlow flow(forest, {{0.0, 0.0, 0.0}, 0.25}, 0.1);
  const auto [worst_u, worst_v, dpdx] = run_channel(forest, flow);
  const auto& g = flow.grid();
  INFO("cells " << g.global_cells() << "; largest |u - u_exact| " << worst_u << ", |v| " << worst_v
                << "; dp/dx " << dpdx << " (exact -1.2); face divergence x dt "
                << flow.face_divergence() * 0.002);
  CHECK(worst_u <= 0.02);  // references.csv: amr_channel_poiseuille
  CHECK(worst_v <= 0.0125);
  CHECK(std::fabs(dpdx + 1.2) <= 0.012);
  CHECK(flow.face_divergence() * 0.002 <= 3e-16);
}

namespace {

// The channel above from rest with the inlet's profile, diffusion implicit
// (CompositeFlow::set_implicit_diffusion), to t = 3 at steps of dt: its
// errors and its velocity per cell, (level, i, j, component).
std::pair<ChannelErrors, std::map<std::array<long, 4>, double>> implicit_startup(double dt) {
  auto spec = coflow::test::forest_2d({8, 4, 1}, {false, false, false}, 1, 4, 3);
  spec.refine = [](int, const Index3& p) { return p[1] == 0 || p[1] == 3; };
  Forest forest(MPI_COMM_WORLD, spec);
  CompositeFlow flow(forest, {{0.0, 0.0, 0.0}, 0.25}, 0.1);
  flow.set_implicit_diffusion(true);
  flow.set_inlet(0, poiseuille);
  flow.set_outlet(1);
  flow.project_initial();
  const int steps = static_cast<int>(std::lround(3.0 / dt));
  for (int n = 0; n < steps; ++n) flow.step(dt);
  const auto& g = flow.grid();
  std::map<std::array<long, 4>, double> u;
  for (long c = 0; c < g.local_cells(); ++c) {
    const auto cell = g.local_cell(c);
    const auto v = forest.data(static_cast<std::size_t>(c / g.cells_per_patch()));
    const auto k = static_cast<std::size_t>(c % g.cells_per_patch()) * 3;
    for (long q = 0; q < 2; ++q)
      u[{cell.level, cell.index[0], cell.index[1], q}] = v[k + static_cast<std::size_t>(q)];
  }
  return {channel_errors(forest, g), u};
}

}  // namespace

TEST_CASE("amr channel: implicit diffusion starts Poiseuille flow from rest at 16x the explicit step",
          "[amr]") {  // 1 rank (unit.amr): 900 steps, 16 s on 4 oversubscribed ranks
  // Steps of 0.02 against the explicit limit h^2 / (8 nu) = 0.00122 on the
  // fine cells, and of 0.005. The inlet fixes the flow rate, so the slowest
  // transient is the first even mode of zero mean, k = 8.99 / H (tan(k H / 2)
  // = k H / 2), decaying as exp(-nu k^2 t): e^-24 at t = 3. Both runs end at
  // the steady state, which the approximate projection lets move a little
  // with the step (2.3e-4 between these two); without the old pressure in
  // the predictor (incremental pressure correction) it moved by 1.5e-3.
  const auto [e, coarse] = implicit_startup(0.02);
  const auto [e_fine, fine] = implicit_startup(0.005);
  long missing = 0;
  const double step_difference = coflow::test::largest_difference(coarse, fine, &missing);
  INFO("largest |u - u_exact| " << e.u << ", |v| " << e.v << "; dp/dx " << e.dpdx
                                << " (exact -1.2); against steps of 0.005: " << step_difference);
  CHECK(e.u <= 0.02);  // references.csv: amr_channel_implicit_startup
  CHECK(e.v <= 0.0125);
  CHECK(std::fabs(e.dpdx + 1.2) <= 0.012);
  CHECK(missing == 0);
  CHECK(step_difference <= 5e-4);  // references.csv: amr_channel_implicit_startup
}

TEST_CASE("amr channel: the half channel with a symmetry face at its centre line", "[amr][mpi]") {
  // The lower half of the channel above, [0, 2] x [0, 0.5]: wall at y = 0,
  // symmetry face at y = 0.5 (no flow through, no shear), the trees along
  // the wall one level finer. Poiseuille flow is the same there: u = 6 y
  // (1 - y), dp/dx = -12 nu U / H^2 with H = 1. Diffusion explicit, and
  // implicit at 50 steps of 0.02 (the symmetry face's conditions on each
  // component in the Helmholtz systems).
  for (bool implicit : {false, true}) {
    auto spec = coflow::test::forest_2d({8, 2, 1}, {false, false, false}, 1, 4, 3);
    spec.refine = [](int, const Index3& p) { return p[1] == 0; };
    Forest forest(MPI_COMM_WORLD, spec);
    CompositeFlow flow(forest, {{0.0, 0.0, 0.0}, 0.25}, 0.1);
    flow.set_symmetry(3);
    flow.set_implicit_diffusion(implicit);
    const auto [worst_u, worst_v, dpdx] = run_channel(forest, flow, implicit ? 50 : 500);
    const auto& g = flow.grid();
    INFO("cells " << g.global_cells() << "; largest |u - u_exact| " << worst_u << ", |v| " << worst_v
                  << "; dp/dx " << dpdx << " (exact -1.2); implicit " << implicit);
    CHECK(worst_u <= 0.02);  // references.csv: amr_half_channel_symmetry
    CHECK(worst_v <= 0.0125);
    CHECK(std::fabs(dpdx + 1.2) <= 0.012);
  }
}
