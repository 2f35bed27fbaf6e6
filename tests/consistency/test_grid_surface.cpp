// The bilinear surface of the pixel grid and its acquisition (grid_surface.hpp).
#include "consistency/grid_surface.hpp"

#include "consistency/acquisition_model.hpp"
#include "util/error.hpp"

#include "test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>

using namespace ddt;

namespace {

// The surface drawn pixel by pixel from its definition: the bilinear
// interpolant at the clamped output centre.
Image reference_surface(const std::vector<double>& v, int W, int H, int C, int out_w, int out_h) {
  Image out(out_w, out_h, C);
  for (int Y = 0; Y < out_h; ++Y)
    for (int X = 0; X < out_w; ++X) {
      const double u = std::clamp((X + 0.5) * W / out_w, 0.5, W - 0.5) - 0.5;
      const double t = std::clamp((Y + 0.5) * H / out_h, 0.5, H - 0.5) - 0.5;
      const int x0 = std::min(W - 1, int(u)), y0 = std::min(H - 1, int(t));
      const int x1 = std::min(W - 1, x0 + 1), y1 = std::min(H - 1, y0 + 1);
      const double fx = u - x0, fy = t - y0;
      for (int c = 0; c < C; ++c) {
        auto at = [&](int x, int y) { return v[(std::size_t(y) * W + x) * C + c]; };
        out.at(X, Y, c) = static_cast<float>((1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
                                             fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1)));
      }
    }
  return out;
}

}  // namespace

TEST_CASE("GridSurface::add_to: draws the clamped bilinear interpolant, any scale") {
  for (auto [W, H, ow, oh] : {std::array{7, 5, 28, 20}, std::array{7, 5, 17, 13}, std::array{1, 4, 3, 9},
                              std::array{6, 1, 13, 3}, std::array{5, 5, 5, 5}}) {
    CAPTURE(W);
    CAPTURE(ow);
    const int C = 2;
    const std::vector<float> f = test::random_values(std::size_t(W) * H * C, 1, 3);
    const std::vector<double> v(f.begin(), f.end());
    const Image expected = reference_surface(v, W, H, C, ow, oh);
    Image out(ow, oh, C, 0.25f);
    GridSurface(W, H, ow, oh, parse_acquisition_model("box")).add_to(out, v);
    double worst = 0;
    for (std::size_t i = 0; i < out.pixels.size(); ++i)
      worst = std::max(worst, std::abs(out.pixels[i] - 0.25 - expected.pixels[i]));
    CHECK(worst < 1e-6);
  }
}

TEST_CASE("GridSurface: acquire is the model's acquisition of the surface, solve its exact inverse") {
  for (const char* name : {"box", "gauss:0.6", "bicubic"})
    for (auto [W, H, ow, oh] : {std::array{9, 7, 36, 28}, std::array{9, 7, 22, 17}, std::array{9, 7, 9, 7},
                                std::array{1, 6, 4, 24}, std::array{8, 3, 81, 31}, std::array{40, 30, 100, 75}}) {
      CAPTURE(name);
      CAPTURE(ow);
      CAPTURE(oh);
      const AcquisitionModel model = parse_acquisition_model(name);
      const GridSurface grid(W, H, ow, oh, model);
      const int C = 3;
      const std::vector<float> f = test::random_values(std::size_t(W) * H * C, 1, 11);
      const std::vector<double> v(f.begin(), f.end());
      const Image acquired = apply_acquisition(model, reference_surface(v, W, H, C, ow, oh), W, H);
      std::vector<double> y, back;
      grid.acquire(v, y, C);
      double worst = 0;
      for (std::size_t i = 0; i < y.size(); ++i) worst = std::max(worst, std::abs(y[i] - acquired.pixels[i]));
      CHECK(worst < 1e-5);
      grid.solve(y, back, C);
      worst = 0;
      for (std::size_t i = 0; i < v.size(); ++i) worst = std::max(worst, std::abs(back[i] - v[i]));
      CHECK(worst < 1e-9);
    }
}

TEST_CASE("GridSurface: at scale 1 under the box model the surface is the samples") {
  const GridSurface grid(6, 4, 6, 4, parse_acquisition_model("box"));
  const std::vector<float> f = test::random_values(24, 1, 2);
  const std::vector<double> v(f.begin(), f.end());
  std::vector<double> y;
  grid.acquire(v, y, 1);
  for (std::size_t i = 0; i < v.size(); ++i) CHECK(y[i] == doctest::Approx(v[i]).epsilon(1e-12));
  CHECK_THROWS_AS(GridSurface(0, 4, 6, 4, parse_acquisition_model("box")), Error);
  std::vector<double> wrong(5);
  CHECK_THROWS_AS(grid.acquire(wrong, y, 1), Error);
}
