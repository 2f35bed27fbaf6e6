#include "eval/classic_resize.hpp"
#include "eval/comparison.hpp"
#include "util/error.hpp"
#include "test_support.hpp"
#include "pipeline/upscale.hpp"

#include <doctest/doctest.h>

using namespace ddt;

TEST_CASE("side_by_side: the right half is the plain DDT output, bit for bit") {
  const Image in = test::sampled_image(20, 14, 3, [](double x, double y, int c) {
    return (x - 2 * y + 3 * c > 0 ? 0.8 : 0.1) + 0.01 * x;
  });
  const Image ddt = upscale(in, 60, 42);
  const Image classic = classic_resize(in, 60, 42, "bicubic");
  const Image both = side_by_side(classic, ddt, 3, 0.0f);
  REQUIRE(both.width == 123);
  REQUIRE(both.height == 42);
  for (int y = 0; y < 42; ++y)
    for (int x = 0; x < 60; ++x)
      for (int c = 0; c < 3; ++c) {
        REQUIRE(both.at(63 + x, y, c) == ddt.at(x, y, c));
        REQUIRE(both.at(x, y, c) == classic.at(x, y, c));
      }
  for (int y = 0; y < 42; ++y)
    for (int x = 60; x < 63; ++x) CHECK(both.at(x, y, 0) == 0.0f);
}

TEST_CASE("side_by_side: separator alpha is opaque - mismatched sizes are an error") {
  const Image a(4, 3, 4, 0.5f), b(4, 3, 4, 0.25f);
  const Image both = side_by_side(a, b, 2, 1.0f, 3);
  CHECK(both.at(4, 1, 3) == 1.0f);
  CHECK(both.at(4, 1, 0) == 1.0f);
  CHECK_THROWS_AS(side_by_side(a, Image(5, 3, 4), 2), Error);
}
