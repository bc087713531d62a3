#include <catch2/catch.hpp>

#include <cstdint>
#include <new>
#include <utility>

#include "coflow/memory.hpp"

using coflow::StridedArrays;

TEST_CASE("strided arrays: zeroed, writable at their stride, movable", "[memory]") {
  constexpr std::size_t stride = (std::size_t(1) << 25) + 296, n = 5000;  // lbm's spaced stride
  StridedArrays<double> a(19, stride, n);
  REQUIRE(a.data() != nullptr);
  CHECK(reinterpret_cast<std::uintptr_t>(a.data()) % (std::size_t(2) << 20) == 0);  // huge-page aligned
  CHECK(a.stride() == stride);
  for (int q = 0; q < 19; ++q) {
    CHECK(a[q * stride] == 0.0);
    CHECK(a[q * stride + n - 1] == 0.0);
    a[q * stride] = q;
    a[q * stride + n - 1] = -q;
  }
  StridedArrays<double> b(std::move(a));
  CHECK(a.data() == nullptr);
  for (int q = 0; q < 19; ++q) {
    CHECK(b[q * stride] == q);
    CHECK(b[q * stride + n - 1] == -q);
  }
  StridedArrays<double> c(3, 8, 8);
  std::swap(b, c);
  CHECK(b.stride() == 8);
  CHECK(c[18 * stride] == 18.0);
}

TEST_CASE("strided arrays: an impossible reservation throws bad_alloc", "[memory]") {
  // 19 x 2^44 doubles: 2.5 PiB of address space, beyond the 128 TiB a process has
  CHECK_THROWS_AS(StridedArrays<double>(19, std::size_t(1) << 44, 10), std::bad_alloc);
}
