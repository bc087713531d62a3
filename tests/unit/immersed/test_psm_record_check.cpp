// psm's check of the particle records it receives (immersed/psm/record_check.hpp).
#include <catch2/catch.hpp>
#include <limits>

#include "immersed/psm/record_check.hpp"

using coflow::immersed::psm::check_record;

namespace {
coflow::config::DomainParams box() {
  coflow::config::DomainParams d;
  d.lower = {0.0, 0.0, 0.0};
  d.upper = {0.032, 0.032, 0.064};
  d.cells = {32, 32, 64};
  d.periodic = {true, false, false};
  return d;
}
coflow::protocol::ParticleRecord bead(double x) {
  coflow::protocol::ParticleRecord r{};
  r.id = 7;
  r.x[0] = x, r.x[1] = 0.016, r.x[2] = 0.03;
  r.radius = 0.004;
  r.mass = 2e-3;
  return r;
}
}  // namespace

TEST_CASE("psm stops at a particle that has blown up, with its id", "[immersed][psm]") {
  const auto d = box();
  // In the box, across a periodic face, just past a wall: covered as before.
  for (double x : {0.016, -0.003, 0.0345, 0.032 + 0.031}) REQUIRE_NOTHROW(check_record(bead(x), d));
  // Far outside (covering it looped once per period crossed, for each of its
  // cells), past the range of a cell index, not a number.
  for (double x : {1.0e6, -0.2, 1.0e300, std::numeric_limits<double>::quiet_NaN()})
    REQUIRE_THROWS_WITH(check_record(bead(x), d), Catch::Matchers::StartsWith("psm: particle 7 has position"));
  auto r = bead(0.016);
  r.v[2] = std::numeric_limits<double>::infinity();
  REQUIRE_THROWS_AS(check_record(r, d), coflow::coupler::SolverError);
  r = bead(0.016);
  r.radius = 0.0;
  REQUIRE_THROWS_AS(check_record(r, d), coflow::coupler::SolverError);
}
