// coupler::check_finite: silent on finite state; on a NaN or an infinity it
// names the component, the field, the item (by id) and the step.
#include <mpi.h>

#include <catch2/catch.hpp>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "coflow/finite.hpp"
#include "coflow/session.hpp"

using namespace coflow::coupler;

TEST_CASE("check_finite names the first non-finite field and item", "[coupler]") {
  std::vector<double> x{0, 0, 0, 1, 1, 1}, v{0, 0, 0, 2, 2, 2};
  const std::vector<std::int64_t> ids{7, 42};
  const FiniteCheck what{"particles (dem)", "particle", "lower the step"};
  CHECK_NOTHROW(check_finite(MPI_COMM_SELF, what, 10, 0.5, {{"position", x}, {"velocity", v}}, 3, ids));
  v[4] = std::numeric_limits<double>::infinity();
  std::string e;
  try {
    check_finite(MPI_COMM_SELF, what, 10, 0.5, {{"position", x}, {"velocity", v}}, 3, ids);
  } catch (const SolverError& err) {
    e = err.what();
  }
  INFO(e);
  CHECK(e.find("particles (dem): velocity is not finite at step 10 (t = 0.5 s), particle 42 (component 1 is inf)") !=
        std::string::npos);
  CHECK(e.find("lower the step") != std::string::npos);
}
