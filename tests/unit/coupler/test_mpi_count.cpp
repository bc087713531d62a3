// coupler::mpi_count: an MPI message's int count, or an error that names the
// message where the count would wrap past 2^31 - 1.
#include <catch2/catch.hpp>
#include <climits>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "coflow/mpi_count.hpp"

using coflow::coupler::mpi_count;

TEST_CASE("mpi_count passes counts up to INT_MAX and refuses larger ones", "[coupler]") {
  CHECK(mpi_count(0, "x") == 0);
  CHECK(mpi_count(std::size_t{INT_MAX}, "x") == INT_MAX);
  // 60 million 36-byte sparse records to one peer: 2.16e9 bytes, past INT_MAX.
  const std::size_t bytes = std::size_t{60'000'000} * 36;
  try {
    mpi_count(bytes, "sparse field (bytes)", "solid");
    FAIL("no error for " << bytes << " bytes");
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    CHECK(m.find("sparse field (bytes) 'solid'") != std::string::npos);
    CHECK(m.find(std::to_string(bytes)) != std::string::npos);
    CHECK(m.find("more ranks") != std::string::npos);
  }
  CHECK_THROWS_AS(mpi_count(std::size_t{INT_MAX} + 1, "x"), std::runtime_error);
}
