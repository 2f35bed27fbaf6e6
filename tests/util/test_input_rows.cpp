// InputRows (util/input_rows.hpp): an input's rows read through a sliding
// window give the image's rows, hold fewer than its height, and read
// released rows again rather than give wrong ones.

#include "util/error.hpp"
#include "util/input_rows.hpp"

#include <doctest/doctest.h>

#include <vector>

using namespace ddt;

namespace {

Image numbered(int W, int H, int C) {
  Image image(W, H, C);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<float>(i);
  return image;
}

// Whether `held` (row 0 the input's row `top`) holds rows [first, end) of `image`.
bool holds(const Image& held, int top, const Image& image, int first, int end) {
  if (top > first || top + held.height < end) return false;
  for (int y = first; y < end; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < image.channels; ++c)
        if (held.at(x, y - top, c) != image.at(x, y, c)) return false;
  return true;
}

}  // namespace

TEST_CASE("InputRows: the whole image is read in place") {
  const Image image = numbered(5, 7, 2);
  InputRows input(image);
  int top = -1;
  const Image& rows = input.rows(2, 4, top);
  CHECK(&rows == &image);
  CHECK(top == 0);
  CHECK(input.whole() == &image);
  CHECK_THROWS_AS(input.rows(3, 8, top), Error);
}

TEST_CASE("InputRows: a sliding window over a source gives the source's rows and holds a few") {
  const int W = 6, H = 300, C = 3;
  const Image image = numbered(W, H, C);
  std::vector<std::pair<int, int>> reads;
  const RowSource source{W, H, C, [&](int first, int end, float* rows) {
                           reads.push_back({first, end});
                           std::copy(image.pixels.begin() + static_cast<std::ptrdiff_t>(image.index(0, first)),
                                     image.pixels.begin() + static_cast<std::ptrdiff_t>(image.index(0, end)), rows);
                         }};
  InputRows input(source);
  CHECK(input.whole() == nullptr);
  CHECK(input.width() == W);
  CHECK(input.height() == H);
  CHECK(input.channels() == C);
  // A pass down the image: each step reads ahead and releases what is behind.
  for (int row = 0; row < H; row += 7) {
    const int first = std::max(0, row - 5), end = std::min(H, row + 20);
    int top = -1;
    const Image& held = input.rows(first, end, top);
    REQUIRE(holds(held, top, image, first, end));
    input.release(row - 5);
  }
  CHECK(input.peak_rows() < 80);
  CHECK(input.rows_read_again() == 0);
  // Every row was read once, in order.
  int next = 0;
  for (const auto& [first, end] : reads) {
    CHECK(first == next);
    next = end;
  }
  CHECK(next == H);

  // Released rows asked for again are read again, not stale.
  int top = -1;
  const Image& again = input.rows(10, 30, top);
  CHECK(holds(again, top, image, 10, 30));
  CHECK(input.rows_read_again() == 20);
  CHECK_THROWS_AS(input.rows(-1, 3, top), Error);
  CHECK_THROWS_AS(input.rows(5, 5, top), Error);
}

TEST_CASE("InputRows: rows not released stay held while later rows are read") {
  const Image image = numbered(4, 100, 1);
  const RowSource source{4, 100, 1, [&](int first, int end, float* rows) {
                           std::copy(image.pixels.begin() + first * 4, image.pixels.begin() + end * 4, rows);
                         }};
  InputRows input(source);
  int top = -1;
  input.rows(0, 10, top);
  input.release(3);
  // Rows [3, 90) asked for while [3, 10) are still wanted: none is read again.
  const Image& held = input.rows(50, 90, top);
  CHECK(top <= 3);
  CHECK(holds(held, top, image, 3, 90));
  CHECK(input.rows_read_again() == 0);
}
