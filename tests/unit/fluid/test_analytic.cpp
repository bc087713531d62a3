#include <catch2/catch.hpp>

#include <cmath>

#include "coflow/catalog.hpp"
#include "coflow/run_config.hpp"
#include "fluid/analytic/analytic_fluid.hpp"

using namespace coflow;

namespace {

struct Built {
  config::Config cfg;
  fluid::FluidParams params;
  fluid::AnalyticParams analytic;
};

Built build(const std::string& analytic_yaml, const std::string& domain_yaml) {
  const std::string text = "run: {name: t, end_time: 1.0}\ndomain: " + domain_yaml +
                           "\nfluid: {solver: analytic, ranks: 1, density: 1.177, viscosity: 1.568e-5, analytic: " +
                           analytic_yaml + "}\n";
  Built b{config::parse_config_node(YAML::Load(text), "t.yaml", coflow::catalog()), {}, {}};
  config::Reader r(b.cfg.resolved["fluid"], "t.yaml", "fluid");
  b.params.visit(r, b.cfg);
  config::Reader a(b.cfg.resolved["fluid"]["analytic"], "t.yaml", "fluid.analytic");
  b.analytic.visit(a);
  return b;
}

}  // namespace

TEST_CASE("grid-turbulence follows Snyder & Lumley's decay laws", "[fluid][analytic]") {
  // Seed 003 §5.4: U = 6.55 m/s, M = 0.0254 m; domain from x/M = 20 to 180.
  const double M = 0.0254, U = 6.55;
  Built b = build("{field: grid-turbulence, flow_axis: 0}",
                  "{lower: [0.508, 0, 0], upper: [4.572, 0.4064, 0.4064], cells: [160, 16, 16]}");
  fluid::AnalyticFluid f({b.cfg, b.params, coupler::Decomposition({160, 16, 16}, 1), 0, MPI_COMM_SELF}, b.analytic);
  const double xi = 68.4;
  const config::Vec3 x{xi * M, 0.2, 0.2};
  // Hand values: w'^2 = U^2 / (42.4 * 52.4), v'^2 = U^2 / (39.4 * 56.4), k = (w'^2 + 2 v'^2) / 2.
  const double w2 = U * U / (42.4 * 52.4), v2 = U * U / (39.4 * 56.4);
  CHECK(f.k_at(x) == Approx(0.5 * (w2 + 2 * v2)).epsilon(1e-14));
  // epsilon = -U dk/dx (seed 003 eq. 5.23), against a central difference.
  const double h = 1e-5;
  const double dk = (f.k_at({x[0] + h, 0.2, 0.2}) - f.k_at({x[0] - h, 0.2, 0.2})) / (2 * h);
  CHECK(f.epsilon_at(x) == Approx(-U * dk).epsilon(1e-7));
  CHECK(f.epsilon_at(x) > 0);
  CHECK(f.velocity_at(x, 0.0)[0] == U);
  CHECK(f.vorticity_at(x, 0.0)[2] == 0.0);
  // k decays downstream.
  CHECK(f.k_at({100 * M, 0.2, 0.2}) < f.k_at(x));
  // The exported fields carry the same numbers cell by cell.
  auto fields = f.fields({"k", "epsilon", "vorticity"});
  REQUIRE(fields.size() == 3);
  const double xc = 0.508 + 0.5 * (4.572 - 0.508) / 160;  // first cell centre
  CHECK(fields[0].data[0] == Approx(f.k_at({xc, 0, 0})).epsilon(1e-15));
}

TEST_CASE("grid-turbulence rejects a domain upstream of x/M = 16", "[fluid][analytic]") {
  const std::string text =
      "run: {name: t, end_time: 1.0}\ndomain: {lower: [0, 0, 0], upper: [1, 0.4, 0.4], cells: [40, 16, 16]}\n"
      "fluid: {solver: analytic, ranks: 1, density: 1.177, viscosity: 1.568e-5, analytic: {field: grid-turbulence}}\n";
  CHECK_THROWS_WITH(config::parse_config_node(YAML::Load(text), "t.yaml", coflow::catalog()),
                    Catch::Contains("fluid.analytic.grid_position") && Catch::Contains("x/M > 16"));
}

TEST_CASE("analytic vorticity is the curl of the analytic velocity", "[fluid][analytic]") {
  for (const std::string a : {"{field: poiseuille, max_velocity: 0.3, flow_axis: 0, wall_axis: 1}",
                              "{field: poiseuille, max_velocity: 0.3, flow_axis: 2, wall_axis: 0}",
                              "{field: taylor-green, max_velocity: 0.3}"}) {
    Built b = build(a, "{lower: [0, 0, 0], upper: [1, 1, 1], cells: [8, 8, 8]}");
    fluid::AnalyticFluid f({b.cfg, b.params, coupler::Decomposition({8, 8, 8}, 1), 0, MPI_COMM_SELF}, b.analytic);
    const config::Vec3 x{0.31, 0.17, 0.62};
    const double h = 1e-6, t = 0.4;
    auto d = [&](int comp, int axis) {
      config::Vec3 p = x, m = x;
      p[axis] += h;
      m[axis] -= h;
      return (f.velocity_at(p, t)[comp] - f.velocity_at(m, t)[comp]) / (2 * h);
    };
    const config::Vec3 w = f.vorticity_at(x, t);
    INFO(a);
    CHECK(w[0] == Approx(d(2, 1) - d(1, 2)).margin(1e-8));
    CHECK(w[1] == Approx(d(0, 2) - d(2, 0)).margin(1e-8));
    CHECK(w[2] == Approx(d(1, 0) - d(0, 1)).margin(1e-8));
  }
}
