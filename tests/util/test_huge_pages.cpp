#include "util/huge_pages.hpp"
#include "util/image.hpp"

#include <doctest/doctest.h>

#include <algorithm>

using namespace ddt;

TEST_CASE("assign_huge: n copies of the value, whatever the vector held, large or small") {
  for (std::size_t n : {std::size_t(0), std::size_t(5), std::size_t(3) << 20}) {  // 3 Mi doubles: 24 MB, advised
    std::vector<double> v(7, -1.0);
    assign_huge(v, n, 0.25);
    CHECK(v.size() == n);
    CHECK(std::all_of(v.begin(), v.end(), [](double x) { return x == 0.25; }));
  }
  const Image image(1024, 1024, 3, 0.5f);  // 12 MB, through the same path
  CHECK(image.pixels.size() == std::size_t(1024) * 1024 * 3);
  CHECK(image.at(1023, 1023, 2) == 0.5f);
  advise_huge_pages(nullptr, 1 << 30);  // advice only: no effect, no failure
}
