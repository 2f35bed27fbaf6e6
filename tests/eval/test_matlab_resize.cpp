// Tests for matlab_resize.hpp: hand-computed cases of MATLAB's imresize 'bicubic'.

#include "eval/matlab_resize.hpp"

#include "util/error.hpp"

#include <doctest/doctest.h>

#include <cmath>

using ddt::Image;

namespace {

// A width x 1 image holding v(i) = i + 1, MATLAB's 1:width.
Image row_ramp(int width) {
  Image img(width, 1, 1);
  for (int i = 0; i < width; ++i) img.at(i, 0) = static_cast<float>(i + 1);
  return img;
}

}  // namespace

TEST_CASE("matlab_imresize_bicubic: a constant image stays constant") {
  Image img(7, 5, 3);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) {
      img.at(x, y, 0) = 0.25f;
      img.at(x, y, 1) = 0.5f;
      img.at(x, y, 2) = 1.0f;
    }
  for (auto [w, h] : {std::pair{14, 10}, std::pair{21, 15}, std::pair{3, 2}, std::pair{9, 4}}) {
    const Image out = ddt::matlab_imresize_bicubic(img, w, h);
    REQUIRE(out.width == w);
    REQUIRE(out.height == h);
    REQUIRE(out.channels == 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        CHECK(out.at(x, y, 0) == doctest::Approx(0.25).epsilon(1e-6));
        CHECK(out.at(x, y, 1) == doctest::Approx(0.5).epsilon(1e-6));
        CHECK(out.at(x, y, 2) == doctest::Approx(1.0).epsilon(1e-6));
      }
  }
}

TEST_CASE("matlab_imresize_bicubic: a ramp enlarged x2 is the ramp at u = x/2 + 1/4 inside") {
  // Keys' kernel reproduces linear functions; output x (1-based) reads u = x/2 + 0.25.
  const Image out = ddt::matlab_imresize_bicubic(row_ramp(8), 16, 1);
  REQUIRE(out.width == 16);
  for (int x = 4; x <= 13; ++x) CHECK(out.at(x - 1, 0) == doctest::Approx(x / 2.0 + 0.25).epsilon(1e-6));
}

TEST_CASE("matlab_imresize_bicubic: symmetric border repeats the edge sample") {
  // Output 1 reads u = 0.75 with taps -1..2 (weights c(1.75), c(0.75), c(0.25),
  // c(1.25) = -0.0234375, 0.2265625, 0.8671875, -0.0703125); the mirror
  // aux = [1:n, n:-1:1] reads taps -1, 0 as samples 2, 1:
  //   -0.0234375*2 + 0.2265625*1 + 0.8671875*1 - 0.0703125*2 = 0.90625.
  // Output 2 reads u = 1.25, taps 0..3 (samples 1, 1, 2, 3) with weights
  //   c(1.25), c(0.25), c(0.75), c(1.75):
  //   -0.0703125 + 0.8671875 + 0.453125 - 0.0703125 = 1.1796875.
  const Image out = ddt::matlab_imresize_bicubic(row_ramp(4), 8, 1);
  CHECK(out.at(0, 0) == doctest::Approx(0.90625).epsilon(1e-7));
  CHECK(out.at(1, 0) == doctest::Approx(1.1796875).epsilon(1e-7));
  // The mirror makes the result symmetric: v -> 5 - v maps the ramp onto itself reversed.
  CHECK(out.at(7, 0) == doctest::Approx(5 - 0.90625).epsilon(1e-7));
  CHECK(out.at(6, 0) == doctest::Approx(5 - 1.1796875).epsilon(1e-7));
}

TEST_CASE("matlab_imresize_bicubic: downscaling x1/2 antialiases and keeps a ramp at u = 2x - 1/2") {
  // Kernel stretched to width 8, taps symmetric about the half-integer u:
  // a linear signal is reproduced away from the border.
  const Image out = ddt::matlab_imresize_bicubic(row_ramp(32), 16, 1);
  REQUIRE(out.width == 16);
  for (int x = 4; x <= 13; ++x) CHECK(out.at(x - 1, 0) == doctest::Approx(2.0 * x - 0.5).epsilon(1e-6));

  // An alternating signal is (nearly) removed by the stretched kernel, kept by point sampling.
  Image zigzag(32, 1, 1);
  for (int i = 0; i < 32; ++i) zigzag.at(i, 0) = (i % 2) ? 1.0f : 0.0f;
  const Image smooth = ddt::matlab_imresize_bicubic(zigzag, 16, 1);
  for (int x = 3; x < 13; ++x) CHECK(std::abs(smooth.at(x, 0) - 0.5f) < 0.05f);
}

TEST_CASE("matlab_imresize_bicubic: separable, a product image gives the product of 1-D resizes") {
  // Width enlarged 2x and height reduced 2x: two different kernels in one call.
  const int w = 6, h = 12;
  Image fx(w, 1, 1), gy(1, h, 1), both(w, h, 1);
  for (int x = 0; x < w; ++x) fx.at(x, 0) = static_cast<float>((x * 7) % 5) / 4.0f;
  for (int y = 0; y < h; ++y) gy.at(0, y) = static_cast<float>((y * 3) % 7) / 6.0f;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) both.at(x, y) = fx.at(x, 0) * gy.at(0, y);
  const Image rx = ddt::matlab_imresize_bicubic(fx, 2 * w, 1);
  const Image ry = ddt::matlab_imresize_bicubic(gy, 1, h / 2);
  const Image r = ddt::matlab_imresize_bicubic(both, 2 * w, h / 2);
  REQUIRE(r.width == 2 * w);
  REQUIRE(r.height == h / 2);
  for (int y = 0; y < h / 2; ++y)
    for (int x = 0; x < 2 * w; ++x) CHECK(r.at(x, y) == doctest::Approx(rx.at(x, 0) * ry.at(0, y)).epsilon(1e-5));
}

TEST_CASE("matlab_imresize_bicubic: channels are resized independently") {
  Image img(5, 4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x)
      for (int c = 0; c < 4; ++c) img.at(x, y, c) = static_cast<float>((x + 2 * y) % 3) * static_cast<float>(c + 1);
  Image first(5, 4, 1);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) first.at(x, y) = img.at(x, y, 0);
  const Image all = ddt::matlab_imresize_bicubic(img, 15, 12);
  const Image one = ddt::matlab_imresize_bicubic(first, 15, 12);
  REQUIRE(all.channels == 4);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 15; ++x)
      for (int c = 0; c < 4; ++c)
        CHECK(all.at(x, y, c) == doctest::Approx(one.at(x, y) * (c + 1)).epsilon(1e-5));
}

TEST_CASE("matlab_imresize_bicubic: bad sizes throw") {
  CHECK_THROWS_AS(ddt::matlab_imresize_bicubic(Image(), 4, 4), ddt::Error);
  CHECK_THROWS_AS(ddt::matlab_imresize_bicubic(Image(2, 2, 1), 0, 4), ddt::Error);
  CHECK_THROWS_AS(ddt::matlab_imresize_bicubic(Image(2, 2, 1), 4, -1), ddt::Error);
}

TEST_CASE("round_to_8bit: rounds to the nearest of 256 levels, halves up, clamps") {
  Image img(6, 1, 1);
  img.at(0, 0) = -0.2f;
  img.at(1, 0) = 1.3f;
  img.at(2, 0) = 0.5f;                    // 127.5 -> 128
  img.at(3, 0) = 10.49f / 255.0f;         // -> 10
  img.at(4, 0) = 10.51f / 255.0f;         // -> 11
  img.at(5, 0) = 200.0f / 255.0f;         // a level stays put
  const Image out = ddt::round_to_8bit(img);
  CHECK(out.at(0, 0) == 0.0f);
  CHECK(out.at(1, 0) == 1.0f);
  CHECK(out.at(2, 0) * 255.0f == doctest::Approx(128));
  CHECK(out.at(3, 0) * 255.0f == doctest::Approx(10));
  CHECK(out.at(4, 0) * 255.0f == doctest::Approx(11));
  CHECK(out.at(5, 0) * 255.0f == doctest::Approx(200));
}
