#include "util/error.hpp"
#include "volume/presmooth.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numeric>

using namespace ddt;

TEST_CASE("smoothed_grid: constants and sigma 0 unchanged - linear ramps kept inside - only the chosen axes move") {
  const std::vector<int> size = {12, 9, 5};
  const int C = 2;
  std::vector<float> v(std::size_t(12 * 9 * 5 * C));
  for (int z = 0; z < 5; ++z)
    for (int y = 0; y < 9; ++y)
      for (int x = 0; x < 12; ++x) {
        const std::size_t i = (std::size_t(z) * 9 + y) * 12 + x;
        v[i * C] = 0.25f;                                   // channel 0: constant
        v[i * C + 1] = 0.1f * x + 0.2f * y + 0.7f * (z % 2);  // channel 1: ramp in x, y; alternating in z
      }
  CHECK(smoothed_grid(v, size, C, {0, 0, 0}) == v);
  const std::vector<float> s = smoothed_grid(v, size, C, {1.0, 1.0, 0.0});
  REQUIRE(s.size() == v.size());
  double worst_constant = 0, worst_ramp = 0, worst_z = 0;
  for (int z = 0; z < 5; ++z)
    for (int y = 3; y < 6; ++y)
      for (int x = 3; x < 9; ++x) {
        const std::size_t i = (std::size_t(z) * 9 + y) * 12 + x;
        worst_constant = std::max(worst_constant, double(std::abs(s[i * C] - 0.25f)));
        worst_ramp = std::max(worst_ramp, double(std::abs(s[i * C + 1] - v[i * C + 1])));
      }
  for (std::size_t i = 0; i < v.size(); i += C) worst_z = std::max(worst_z, double(std::abs(s[i] - 0.25f)));
  CHECK(worst_constant < 1e-6);
  CHECK(worst_ramp < 1e-4);  // a linear ramp is its own Gaussian average away from the border
  CHECK(worst_z < 1e-6);
  // Along z it does smooth: the alternating values come closer.
  const std::vector<float> sz = smoothed_grid(v, size, C, {0.0, 0.0, 1.0});
  const std::size_t a = (std::size_t(2) * 9 + 4) * 12 + 6, b = (std::size_t(3) * 9 + 4) * 12 + 6;
  CHECK(std::abs(sz[a * C + 1] - sz[b * C + 1]) < 0.5 * std::abs(v[a * C + 1] - v[b * C + 1]));
  CHECK_THROWS_AS(smoothed_grid(v, {12, 9}, C, {1, 1}), Error);
  CHECK_THROWS_AS(smoothed_grid(v, size, C, {1, 1}), Error);
}
