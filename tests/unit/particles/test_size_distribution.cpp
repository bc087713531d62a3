// Log-normal diameters truncated by resampling (DEM and DPM draw them alike):
// no draw above the cutoff, none piled onto it, and the sample mean equals the
// mean of the truncated density, exp(mu + sigma^2/2) Phi((ln c - mu - sigma^2)/sigma)
// / Phi((ln c - mu)/sigma).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "particles/size_distribution.hpp"

using coflow::particles::lognormal_cutoff;
using coflow::particles::truncated_lognormal;

TEST_CASE("log-normal diameters are truncated by resampling, not clamped", "[particles]") {
  // A wide distribution (s = 2 D): the tail beyond D + 6 s carries 0.4 %
  // of the mass (8 % of the mean): clamping would put 0.4 % of the draws on the cutoff.
  const double D = 1e-3, s = 2e-3, c = lognormal_cutoff(D, s);
  const double s2 = std::log(1.0 + s * s / (D * D)), mu = std::log(D) - 0.5 * s2, sigma = std::sqrt(s2);
  auto Phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  const double tail = 1.0 - Phi((std::log(c) - mu) / sigma);
  REQUIRE(tail > 0.003);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int n = 200000;
  double sum = 0.0, sum2 = 0.0, largest = 0.0;
  long at_cutoff = 0;
  for (int i = 0; i < n; ++i) {
    const double d = truncated_lognormal(D, s, [&](int) { return normal(rng); });
    largest = std::max(largest, d);
    at_cutoff += d == c;
    sum += d;
    sum2 += d * d;
  }
  CHECK(largest <= c);
  CHECK(at_cutoff == 0);
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  const double expected = std::exp(mu + 0.5 * s2) * Phi((std::log(c) - mu - s2) / sigma) / Phi((std::log(c) - mu) / sigma);
  INFO("mean " << mean << " expected " << expected << " (untruncated " << D << ")");
  CHECK(std::abs(mean - expected) < 4.0 * sd / std::sqrt(n));  // 4 standard errors
  CHECK(std::abs(mean - D) > 4.0 * sd / std::sqrt(n));         // and the truncation shows
}
