// The halo limit's mean-keeping shift (halo_limit.hpp): the mean of the
// clamped, shifted values is the one asked for, whatever the footprint.
#include "consistency/halo_limit.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

double clamped_mean(const std::vector<float>& values, double t, double lo, double hi) {
  double sum = 0;
  for (float v : values) sum += std::clamp(v + t, lo, hi);
  return sum / values.size();
}

}  // namespace

TEST_CASE("mean_keeping_shift: the clamped values keep the mean asked for") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-0.5f, 1.5f);
  // Up to x10's 100 pixels: the breakpoints on the stack (64 pixels and
  // fewer) and on the heap.
  std::uniform_int_distribution<int> size(1, 100);
  const double inf = std::numeric_limits<double>::infinity();
  int checked = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<float> values(size(rng));
    for (float& v : values) v = value(rng);
    // Bounds: both finite, one side open, or none; some tight enough that
    // most values are clamped (the case that once took 20 steps).
    double lo = std::uniform_real_distribution<double>(-0.2, 0.6)(rng);
    double hi = lo + std::uniform_real_distribution<double>(0.0, 0.8)(rng);
    if (trial % 7 == 1) lo = -inf;
    if (trial % 11 == 2) hi = inf;
    const double lowest = std::isfinite(lo) ? lo : -1, highest = std::isfinite(hi) ? hi : 2;
    const double mean = std::uniform_real_distribution<double>(lowest, highest)(rng);
    const double t = ddt::mean_keeping_shift(values, mean, lo, hi);
    CAPTURE(trial);
    REQUIRE(std::isfinite(t));
    CHECK(std::abs(clamped_mean(values, t, lo, hi) - mean) < 1e-9);
    ++checked;
  }
  CHECK(checked == 20000);
  // A mean on a bound leaves the flat bound: every value clamped to it.
  const std::vector<float> values = {0.1f, 0.4f, 0.9f};
  const double t = ddt::mean_keeping_shift(values, 0.2, -inf, 0.2);
  for (float v : values) CHECK(std::min(v + t, 0.2) == doctest::Approx(0.2).epsilon(1e-9));
}
