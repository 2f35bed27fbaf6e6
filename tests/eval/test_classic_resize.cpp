// Tests for classic_resize.hpp: OIIO's resamplers behave as the textbook
// interpolators they are named after when enlarging.

#include "eval/classic_resize.hpp"

#include "util/error.hpp"

#include <doctest/doctest.h>

#include <string>

using ddt::Image;

namespace {

Image impulse_row(int width, int at) {
  Image img(width, 1, 1);
  img.at(at, 0) = 1.0f;
  return img;
}

}  // namespace

TEST_CASE("classic_resize: nearest replicates pixels for integer enlargement") {
  Image img(3, 2, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 2; ++c) img.at(x, y, c) = static_cast<float>(10 * y + x + 100 * c);
  const Image out = ddt::classic_resize(img, 9, 4, "nearest");  // x3 across, x2 down
  REQUIRE(out.width == 9);
  REQUIRE(out.height == 4);
  REQUIRE(out.channels == 2);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 9; ++x)
      for (int c = 0; c < 2; ++c) CHECK(out.at(x, y, c) == img.at(x / 3, y / 2, c));
}

TEST_CASE("classic_resize: bilinear x2 interpolates linearly between pixel centres") {
  // Output X samples input position (X + 0.5) / 2 - 0.5 (centre convention);
  // an impulse at 4 spreads as 0.25, 0.75, 0.75, 0.25 over outputs 7..10.
  const Image out = ddt::classic_resize(impulse_row(8, 4), 16, 1, "bilinear");
  CHECK(out.at(6, 0) == doctest::Approx(0.0).scale(1));
  CHECK(out.at(7, 0) == doctest::Approx(0.25));
  CHECK(out.at(8, 0) == doctest::Approx(0.75));
  CHECK(out.at(9, 0) == doctest::Approx(0.75));
  CHECK(out.at(10, 0) == doctest::Approx(0.25));
  CHECK(out.at(11, 0) == doctest::Approx(0.0).scale(1));
}

TEST_CASE("classic_resize: bicubic x2 is Keys' kernel with a = -0.5 at its natural width") {
  // Weights at distances 0.25, 0.75, 1.25, 1.75 input pixels.
  const Image out = ddt::classic_resize(impulse_row(8, 4), 16, 1, "bicubic");
  CHECK(out.at(5, 0) == doctest::Approx(-0.0234375).epsilon(1e-4));
  CHECK(out.at(6, 0) == doctest::Approx(-0.0703125).epsilon(1e-4));
  CHECK(out.at(7, 0) == doctest::Approx(0.2265625).epsilon(1e-4));
  CHECK(out.at(8, 0) == doctest::Approx(0.8671875).epsilon(1e-4));
  CHECK(out.at(9, 0) == doctest::Approx(0.8671875).epsilon(1e-4));
  CHECK(out.at(4, 0) == doctest::Approx(0.0).scale(1));
}

TEST_CASE("classic_resize: lanczos x2 spans three input pixels each side") {
  const Image out = ddt::classic_resize(impulse_row(16, 8), 32, 1, "lanczos");
  // Output X samples input position (X + 0.5) / 2; the impulse's centre is 8.5.
  // Non-zero closer than 3 input pixels (X = 11..22), zero beyond.
  CHECK(out.at(16, 0) == doctest::Approx(out.at(17, 0)));
  CHECK(out.at(16, 0) > 0.85f);
  CHECK(out.at(13, 0) < 0.0f);  // distance 1.75: the negative lobe
  CHECK(out.at(11, 0) != 0.0f);  // distance 2.75
  CHECK(out.at(22, 0) != 0.0f);
  CHECK(out.at(10, 0) == doctest::Approx(0.0).scale(1));  // distance 3.25
  CHECK(out.at(23, 0) == doctest::Approx(0.0).scale(1));
}

TEST_CASE("classic_resize: a constant image stays constant with every method") {
  const Image img(5, 4, 3, 0.375f);
  for (const auto& m : ddt::classic_methods()) {
    const Image out = ddt::classic_resize(img, 15, 12, m);
    for (float v : out.pixels) CHECK(v == doctest::Approx(0.375f).epsilon(1e-5));
  }
}

TEST_CASE("classic_resize: unknown method throws listing the valid names") {
  const Image img(2, 2, 1);
  try {
    ddt::classic_resize(img, 4, 4, "sinc");
    FAIL("no exception");
  } catch (const ddt::Error& e) {
    const std::string msg = e.what();
    CHECK(msg.find("sinc") != std::string::npos);
    for (const auto& m : ddt::classic_methods()) CHECK(msg.find(m) != std::string::npos);
  }
  CHECK_THROWS_AS(ddt::classic_resize(Image(), 4, 4, "nearest"), ddt::Error);
  CHECK_THROWS_AS(ddt::classic_resize(img, 0, 4, "nearest"), ddt::Error);
  CHECK(ddt::classic_methods() == std::vector<std::string>{"nearest", "bilinear", "bicubic", "lanczos"});
}
