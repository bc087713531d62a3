#include <catch2/catch.hpp>

#include "coflow/catalog.hpp"
#include "coflow/config.hpp"
#include "coflow/run_config.hpp"

using namespace coflow::config;

namespace {

struct Sample {
  double tau = 0.8;
  int n = 3;
  std::string lattice = "D3Q19";
  Vec3 g{0, 0, -9.81};
  AutoDouble dt;
  Distribution d{Distribution::Kind::fixed, 1e-3, 0};
  void visit(Visitor& v) {
    v("tau", tau, "relaxation time", greater(0.5));
    v("n", n, "count", at_least(1));
    v("lattice", lattice, "stencil", one_of({"D2Q9", "D3Q19"}));
    v("g", g, "gravity");
    v("dt", dt, "time step", positive());
    v("d", d, "diameter", positive());
  }
};

std::vector<Problem> read(const std::string& text, Sample& s) {
  Reader r(YAML::Load(text), "x.yaml");
  s.visit(r);
  r.finish();
  return r.problems();
}

}  // namespace

TEST_CASE("reader keeps defaults and reads given keys", "[config]") {
  Sample s;
  auto p = read("tau: 0.9\ndt: auto\nd: {lognormal: {mean: 6.0e-5, std: 1.0e-5}}\n", s);
  REQUIRE(p.empty());
  CHECK(s.tau == 0.9);
  CHECK(s.n == 3);
  CHECK(s.dt.is_auto);
  CHECK(s.d.kind == Distribution::Kind::lognormal);
  CHECK(s.d.a == 6.0e-5);
  CHECK(s.d.b == 1.0e-5);
}

TEST_CASE("reader reports rule violations with the position", "[config]") {
  Sample s;
  auto p = read("n: 2\ntau: 0.5\n", s);
  REQUIRE(p.size() == 1);
  CHECK(p[0].format() == "x.yaml:2:6: tau: must be > 0.5 (got 0.5)");
}

TEST_CASE("unknown keys get a suggestion, duplicates are rejected", "[config]") {
  Sample s;
  auto p = read("lattise: D2Q9\ntau: 0.6\ntau: 0.7\n", s);
  REQUIRE(p.size() == 2);
  CHECK(p[0].message == "duplicate key (first given on line 2); keep only one");
  CHECK(p[0].line == 3);
  CHECK(p[1].message.rfind("unknown key 'lattise'; did you mean 'lattice'?", 0) == 0);
}

TEST_CASE("a misspelt value is never replaced by the default", "[config]") {
  Sample s;
  auto p = read("lattice: D3Q91\n", s);
  REQUIRE(p.size() == 1);
  CHECK(p[0].message.find("did you mean 'D3Q19'?") != std::string::npos);
}

TEST_CASE("integers accept integral literals only", "[config]") {
  Sample s;
  CHECK(read("n: 1e4\n", s).empty());
  CHECK(s.n == 10000);
  CHECK(read("n: 2.5\n", s).size() == 1);
}

TEST_CASE("resolved configuration round-trips doubles exactly", "[config]") {
  Sample s;
  Reader r(YAML::Load("tau: 0.1\n"), "x.yaml");
  s.visit(r);
  YAML::Node out = r.resolved();
  CHECK(out["tau"].Scalar() == "0.1");
  CHECK(out["tau"].as<double>() == 0.1);
  CHECK(out["n"].as<int>() == 3);
  CHECK(out["dt"].Scalar() == "auto");
}

TEST_CASE("describer lists every key with type, default and rule", "[config]") {
  Sample s;
  Describer d("lbm");
  s.visit(d);
  REQUIRE(d.rows().size() == 6);
  CHECK(d.rows()[0].path == "lbm.tau");
  CHECK(d.rows()[0].default_value == "0.8");
  CHECK(d.rows()[0].rule == "> 0.5");
  CHECK(d.rows()[2].rule == "one of: D2Q9 | D3Q19");
}

TEST_CASE("overrides create and replace keys", "[config]") {
  YAML::Node root = YAML::Load("fluid: {lbm: {tau: 0.8}}");
  apply_override(root, "fluid.lbm.tau=0.9");
  apply_override(root, "domain.cells=[8, 8, 1]");
  CHECK(root["fluid"]["lbm"]["tau"].as<double>() == 0.9);
  CHECK(root["domain"]["cells"][2].as<int>() == 1);
  CHECK_THROWS_AS(apply_override(root, "no-equals-sign"), ConfigError);
}

TEST_CASE("closest word by edit distance", "[config]") {
  CHECK(closest("viscosty", {"density", "viscosity"}) == "viscosity");
  CHECK(closest("zzzzzz", {"density", "viscosity"}).empty());
}

TEST_CASE("whole configuration: defaults, hash, output directory", "[config]") {
  const char* text = R"(
run: {name: demo, end_time: 1.0}
domain: {lower: [0, 0, 0], upper: [1, 1, 1], cells: [4, 4, 4]}
fluid:
  solver: fv
  density: 1.0
  viscosity: 0.1
  boundaries: {x-: {type: wall}, x+: {type: pressure, value: 2.5}, y-: {type: velocity, value: [0.1, 0, 0]}}
)";
  Config a = parse_config_node(YAML::Load(text), "a.yaml", coflow::catalog());
  Config b = parse_config_node(YAML::Load(text), "b.yaml", coflow::catalog());
  CHECK(a.output_dir() == "out/demo");
  CHECK(a.has("fluid"));
  CHECK_FALSE(a.has("particles"));
  CHECK(a.component("fluid").ranks == 1);
  CHECK(a.hash == b.hash);
  CHECK(a.resolved["coupling"]["scheme"].as<std::string>() == "serial-explicit");
  // The resolved file (what the components read) is itself a valid
  // configuration, and a component reading it with the open catalogue (built
  // outside the tree, linking libcoflow alone) gets the same hash as one with
  // every schema: the hash is of what was read.
  const YAML::Node resolved = YAML::Load(YAML::Dump(a.resolved));
  Config c = parse_config_node(YAML::Clone(resolved), "c.yaml", coflow::catalog());
  Config o = parse_config_node(YAML::Clone(resolved), "c.yaml", open_catalog());
  CHECK(o.hash == c.hash);
  CHECK(o.component("fluid").variant == "fv");
  CHECK(c.hash != a.hash);  // another text
  CHECK_FALSE(a.resolved["fluid"]["boundaries"]["x-"]["value"].IsDefined());
  CHECK(a.resolved["fluid"]["boundaries"]["x+"]["value"].as<double>() == 2.5);
  // Faces the file leaves out are walls, and the resolved file says so.
  for (const char* face : {"y+", "z-", "z+"})
    CHECK(a.resolved["fluid"]["boundaries"][face]["type"].as<std::string>() == "wall");
}

TEST_CASE("particle faces left out are resolved to what the solver uses", "[config]") {
  const char* text = R"(
run: {name: demo, end_time: 1.0}
domain: {lower: [0, 0, 0], upper: [1, 1, 1], cells: [4, 4, 4], periodic: [false, true, false]}
particles:
  solver: dpm
  species: {sand: {density: 2500.0, diameter: 1.0e-3}}
  boundaries: {x+: outlet, z-: symmetry}
)";
  const Config a = parse_config_node(YAML::Load(text), "a.yaml", coflow::catalog());
  const YAML::Node b = a.resolved["particles"]["boundaries"];
  CHECK(b["x-"].as<std::string>() == "wall");
  CHECK(b["x+"].as<std::string>() == "outlet");
  CHECK(b["y-"].as<std::string>() == "periodic");
  CHECK(b["y+"].as<std::string>() == "periodic");
  CHECK(b["z-"].as<std::string>() == "symmetry");
  CHECK(b["z+"].as<std::string>() == "wall");
  // The resolved file reads back to the same faces.
  const Config c = parse_config_node(YAML::Load(YAML::Dump(a.resolved)), "c.yaml", coflow::catalog());
  CHECK(c.resolved["particles"]["boundaries"]["z+"].as<std::string>() == "wall");
}
