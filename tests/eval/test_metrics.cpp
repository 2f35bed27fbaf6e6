// Tests for metrics.hpp: BT.601 luma, shave, PSNR and SSIM on hand-computed cases.

#include "eval/metrics.hpp"

#include "util/error.hpp"

#include <doctest/doctest.h>

#include <cmath>

using ddt::Image;

namespace {

Image grey(int w, int h, float v) { return Image(w, h, 1, v); }

// A deterministic textured plane in 0..255.
Eigen::ArrayXXd texture(int rows, int cols, int seed) {
  Eigen::ArrayXXd p(rows, cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) p(r, c) = static_cast<double>((r * 37 + c * 91 + seed * 53 + r * c) % 256);
  return p;
}

}  // namespace

TEST_CASE("luma_bt601: black is 16, white is 235, grey equals replicated RGB") {
  Image rgb(2, 1, 3);
  for (int c = 0; c < 3; ++c) rgb.at(1, 0, c) = 1.0f;
  const Eigen::ArrayXXd y = ddt::luma_bt601(rgb);
  REQUIRE(y.rows() == 1);
  REQUIRE(y.cols() == 2);
  CHECK(y(0, 0) == doctest::Approx(16.0));
  CHECK(y(0, 1) == doctest::Approx(16.0 + 65.481 + 128.553 + 24.966));  // 235
  CHECK(y(0, 1) == doctest::Approx(235.0));

  Image pure(3, 1, 4);  // R, G, B pure, alpha ignored
  for (int c = 0; c < 3; ++c) pure.at(c, 0, c) = 1.0f;
  for (int x = 0; x < 3; ++x) pure.at(x, 0, 3) = 0.25f;
  const Eigen::ArrayXXd yp = ddt::luma_bt601(pure);
  CHECK(yp(0, 0) == doctest::Approx(16.0 + 65.481));
  CHECK(yp(0, 1) == doctest::Approx(16.0 + 128.553));
  CHECK(yp(0, 2) == doctest::Approx(16.0 + 24.966));

  const float v = 0.4f;
  Image g(1, 1, 1, v), same(1, 1, 3, v);
  CHECK(ddt::luma_bt601(g)(0, 0) == doctest::Approx(ddt::luma_bt601(same)(0, 0)));
}

TEST_CASE("luma_bt601: rows of the plane are image rows") {
  Image img(3, 2, 1);
  img.at(2, 1) = 1.0f;  // x = 2, y = 1
  const Eigen::ArrayXXd y = ddt::luma_bt601(img);
  REQUIRE(y.rows() == 2);
  REQUIRE(y.cols() == 3);
  CHECK(y(1, 2) == doctest::Approx(235.0));
  CHECK(y(0, 2) == doctest::Approx(16.0));
}

TEST_CASE("shave: drops the border on every side") {
  Eigen::ArrayXXd p(6, 8);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 8; ++c) p(r, c) = 10 * r + c;
  const Eigen::ArrayXXd s = ddt::shave(p, 2);
  REQUIRE(s.rows() == 2);
  REQUIRE(s.cols() == 4);
  CHECK(s(0, 0) == 22);
  CHECK(s(1, 3) == 35);
  CHECK(ddt::shave(p, 0).size() == p.size());
  CHECK_THROWS_AS(ddt::shave(p, 3), ddt::Error);  // 6 rows - 2*3 leaves nothing
  CHECK_THROWS_AS(ddt::shave(p, -1), ddt::Error);
}

TEST_CASE("psnr: identical planes give +infinity") {
  const Eigen::ArrayXXd a = texture(5, 7, 1);
  const double v = ddt::psnr(a, a);
  CHECK(std::isinf(v));
  CHECK(v > 0);
}

TEST_CASE("psnr: known MSE gives 10 log10(255^2 / MSE)") {
  Eigen::ArrayXXd a = Eigen::ArrayXXd::Zero(4, 4), b = Eigen::ArrayXXd::Zero(4, 4);
  b += 1.0;  // MSE 1
  CHECK(ddt::psnr(a, b) == doctest::Approx(20 * std::log10(255.0)));  // 48.1308
  CHECK(ddt::psnr(a, b) == doctest::Approx(48.1308).epsilon(1e-5));
  b(0, 0) = 41;  // squared errors 1681 + 15 * 1 -> MSE 1696 / 16 = 106
  CHECK(ddt::psnr(a, b) == doctest::Approx(10 * std::log10(255.0 * 255.0 / 106.0)));
  CHECK(ddt::psnr(a, a + 255.0) == doctest::Approx(0.0));
  CHECK_THROWS_AS(ddt::psnr(a, Eigen::ArrayXXd::Zero(4, 5)), ddt::Error);
}

TEST_CASE("psnr_y: a grey offset of 1/219 is one Y level, 48.13 dB") {
  // Y = 16 + 219 v for grey v in 0..1, so v + 1/219 moves Y by exactly 1.
  const Image a = grey(20, 16, 0.3f), b = grey(20, 16, 0.3f + 1.0f / 219.0f);
  CHECK(ddt::psnr_y(a, b, 2) == doctest::Approx(48.1308).epsilon(1e-4));
  CHECK(std::isinf(ddt::psnr_y(a, a, 0)));
}

TEST_CASE("psnr_y: the shaved border does not count") {
  Image a = grey(10, 10, 0.5f), b = a;
  for (int i = 0; i < 10; ++i) b.at(i, 0) = b.at(0, i) = 0.0f;  // wreck the first row and column
  CHECK(std::isinf(ddt::psnr_y(a, b, 1)));
  CHECK(std::isfinite(ddt::psnr_y(a, b, 0)));
  CHECK_THROWS_AS(ddt::psnr_y(a, grey(10, 9, 0.5f), 1), ddt::Error);
}

TEST_CASE("ssim: identical planes give exactly 1") {
  const Eigen::ArrayXXd a = texture(30, 25, 3);
  CHECK(ddt::ssim(a, a) == doctest::Approx(1.0).epsilon(1e-12));
  const Image img = grey(24, 24, 0.7f);
  CHECK(ddt::ssim_y(img, img, 4) == doctest::Approx(1.0).epsilon(1e-12));
}

TEST_CASE("ssim: two constants give (2 m1 m2 + C1) / (m1^2 + m2^2 + C1)") {
  // No variance: the contrast-structure factor is C2 / C2 = 1.
  const double m1 = 100, m2 = 110, c1 = (0.01 * 255) * (0.01 * 255);
  const Eigen::ArrayXXd a = Eigen::ArrayXXd::Constant(15, 12, m1), b = Eigen::ArrayXXd::Constant(15, 12, m2);
  CHECK(ddt::ssim(a, b) == doctest::Approx((2 * m1 * m2 + c1) / (m1 * m1 + m2 * m2 + c1)).epsilon(1e-12));
}

TEST_CASE("ssim: 11x11 valid window, symmetric, below 1 for a distorted plane") {
  const Eigen::ArrayXXd a = texture(11, 11, 1), b = texture(11, 11, 2);
  const double s = ddt::ssim(a, b);  // one window position
  CHECK(s < 1.0);
  CHECK(s == doctest::Approx(ddt::ssim(b, a)).epsilon(1e-12));
  CHECK_THROWS_AS(ddt::ssim(texture(10, 11, 1), texture(10, 11, 2)), ddt::Error);

  // Noise lowers SSIM, more noise lowers it more.
  const Eigen::ArrayXXd base = texture(40, 40, 5) * 0.5 + 64;
  Eigen::ArrayXXd noise(40, 40);
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 40; ++c) noise(r, c) = ((r * 13 + c * 7) % 5) - 2.0;
  const double light = ddt::ssim(base, base + noise), heavy = ddt::ssim(base, base + 8 * noise);
  CHECK(light < 1.0);
  CHECK(heavy < light);
  CHECK(heavy > 0.0);
}

TEST_CASE("ssim: a single window equals the Gaussian-weighted formula computed directly") {
  const Eigen::ArrayXXd a = texture(11, 11, 7), b = texture(11, 11, 9);
  double wsum = 0;
  Eigen::ArrayXXd w(11, 11);
  for (int r = 0; r < 11; ++r)
    for (int c = 0; c < 11; ++c) wsum += w(r, c) = std::exp(-((r - 5.0) * (r - 5.0) + (c - 5.0) * (c - 5.0)) / 4.5);
  w /= wsum;
  const double mu1 = (w * a).sum(), mu2 = (w * b).sum();
  const double s11 = (w * a * a).sum() - mu1 * mu1, s22 = (w * b * b).sum() - mu2 * mu2;
  const double s12 = (w * a * b).sum() - mu1 * mu2;
  const double c1 = 6.5025, c2 = 58.5225;
  const double expected = ((2 * mu1 * mu2 + c1) * (2 * s12 + c2)) / ((mu1 * mu1 + mu2 * mu2 + c1) * (s11 + s22 + c2));
  CHECK(ddt::ssim(a, b) == doctest::Approx(expected).epsilon(1e-10));
}
