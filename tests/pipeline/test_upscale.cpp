#include "util/error.hpp"
#include "io/image_io.hpp"
#include "test_support.hpp"
#include "eval/matlab_resize.hpp"
#include "eval/synthetic_scenes.hpp"
#include "pipeline/upscale.hpp"

#include <OpenImageIO/imagebufalgo.h>
#include <doctest/doctest.h>

#include <cmath>

using namespace ddt;

TEST_CASE("upscale: a constant image stays constant, with no flips") {
  const Image in(13, 9, 3, 0.375f);
  UpscaleStats st;
  const Image out = upscale(in, 52, 36, {}, &st);
  CHECK(out.width == 52);
  CHECK(out.height == 36);
  CHECK(st.flips == 0);
  for (float v : out.pixels) CHECK(v == 0.375f);
}

TEST_CASE("upscale: alpha is interpolated but never drives flips") {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0, 1);
  Image in(12, 12, 4, 0.5f);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 12; ++x) in.at(x, y, 3) = u(rng);
  UpscaleOptions opt;
  opt.alpha_channel = 3;
  opt.model.kind = AcquisitionModel::Kind::point;  // samples reproduced
  UpscaleStats st;
  const Image out = upscale(in, 36, 36, opt, &st);
  CHECK(st.flips == 0);
  CHECK(out.at(4, 7, 3) == in.at(1, 2, 3));  // sample reproduced at scale 3
  opt.alpha_channel = -1;
  upscale(in, 36, 36, opt, &st);
  CHECK(st.flips > 0);
}

TEST_CASE("upscale: luma cost uses one channel and still flips on an edge") {
  Image in = test::sampled_image(16, 16, 3, [](double x, double y, int c) { return x + 0.5 * y > 12 ? 0.9 - 0.1 * c : 0.1; });
  UpscaleOptions opt;
  opt.luma_cost = true;
  UpscaleStats st;
  upscale(in, 64, 64, opt, &st);
  CHECK(st.flips > 0);
  CHECK(st.cost_after < st.cost_before);
}

TEST_CASE("upscale: bad options are errors, not crashes") {
  const Image in(4, 4, 1, 0.0f);
  CHECK_THROWS_AS(upscale(Image{}, 4, 4), Error);
  CHECK_THROWS_AS(upscale(in, 0, 4), Error);
  UpscaleOptions opt;
  opt.cost = "nope";
  CHECK_THROWS_AS(upscale(in, 8, 8, opt), Error);
}

TEST_CASE("upscale: degenerate shapes (1x1, a row, a column) work") {
  for (auto [w, h] : {std::pair{1, 1}, std::pair{7, 1}, std::pair{1, 7}}) {
    Image in = test::sampled_image(w, h, 1, [](double x, double y, int) { return 0.1 * x + 0.1 * y; });
    UpscaleOptions point;
    point.model.kind = AcquisitionModel::Kind::point;
    const Image out = upscale(in, w * 3, h * 3, point);
    CHECK(out.width == w * 3);
    CHECK(out.at(3 * (w - 1) + 1, 3 * (h - 1) + 1) == doctest::Approx(in.at(w - 1, h - 1)));
    CHECK(out.at(0, 0) == doctest::Approx(in.at(0, 0)));
  }
}

TEST_CASE("upscale: the ImageBuf forms size dst from the options and report errors on it") {
  OIIO::ImageBuf src(OIIO::ImageSpec(8, 6, 3, OIIO::TypeDesc::FLOAT));
  const float grey[3] = {0.2f, 0.4f, 0.6f};
  OIIO::ImageBufAlgo::fill(src, grey);
  UpscaleOptions options;
  options.scale = 3;
  OIIO::ImageBuf dst;
  UpscaleStats stats;
  REQUIRE(upscale(dst, src, options, {}, 0, &stats));
  CHECK(dst.spec().width == 24);
  CHECK(dst.spec().height == 18);
  CHECK(dst.spec().nchannels == 3);
  CHECK(stats.triangles == 2 * 7 * 5);
  float px[3];
  dst.getpixel(5, 5, px, 3);
  CHECK(px[1] == doctest::Approx(0.4f));
  options.scale = 0;
  options.width = 16;  // the height follows the aspect
  const OIIO::ImageBuf by_width = upscale(src, options);
  CHECK(by_width.spec().width == 16);
  CHECK(by_width.spec().height == 12);
  OIIO::ImageBuf bad;
  options.width = 0;  // no size at all
  CHECK_FALSE(upscale(bad, src, options));
  CHECK(bad.has_error());
  CHECK(bad.geterror().find("--scale") != std::string::npos);
  options.scale = 2;
  options.cost = "nope";
  const OIIO::ImageBuf failed = upscale(src, options);
  CHECK(failed.has_error());
  CHECK(failed.geterror().find("unknown cost 'nope'") != std::string::npos);
}

TEST_CASE("upscale: an ROI is that window of the whole output, and nthreads does not change it") {
  const Image in = test::sampled_image(19, 15, 3, [](double x, double y, int c) {
    return 0.5 + 0.4 * std::sin(0.8 * x + 0.3 * c) * std::cos(0.5 * y + 0.2 * x);
  });
  const OIIO::ImageBuf src = buf_from_image(in);
  UpscaleOptions options;
  options.scale = 2.5;
  const Image whole = upscale(in, 48, 38, options);  // round(19 * 2.5) x round(15 * 2.5)
  const OIIO::ImageBuf full = upscale(src, options, {}, 1);
  REQUIRE_FALSE(full.has_error());
  CHECK(image_from_buf(full).pixels == whole.pixels);
  for (int nthreads : {0, 1, 2}) {
    CAPTURE(nthreads);
    const OIIO::ROI roi(7, 30, 11, 38, 0, 1, 1, 3);  // reaches the bottom edge; channels 1 and 2
    const OIIO::ImageBuf window = upscale(src, options, roi, nthreads);
    REQUIRE_FALSE(window.has_error());
    CHECK(window.roi() == OIIO::ROI(7, 30, 11, 38, 0, 1, 0, 2));
    CHECK(window.spec().full_width == 48);
    CHECK(window.spec().full_height == 38);
    int differing = 0;
    for (int y = roi.ybegin; y < roi.yend; ++y)
      for (int x = roi.xbegin; x < roi.xend; ++x)
        for (int c = 0; c < 2; ++c) differing += window.getchannel(x, y, 0, c) != whole.at(x, y, c + 1);
    CHECK(differing == 0);
  }
  // Into an initialized dst: only the window is written.
  OIIO::ImageBuf canvas(OIIO::ImageSpec(48, 38, 3, OIIO::TypeDesc::FLOAT));
  const float red[3] = {1, 0, 0};
  OIIO::ImageBufAlgo::fill(canvas, red);
  REQUIRE(upscale(canvas, src, options, OIIO::ROI(0, 10, 0, 5)));
  CHECK(canvas.getchannel(3, 4, 0, 0) == whole.at(3, 4, 0));
  CHECK(canvas.getchannel(3, 4, 0, 0) != 1.0f);
  CHECK(canvas.getchannel(10, 4, 0, 0) == 1.0f);
  CHECK(canvas.getchannel(3, 5, 0, 0) == 1.0f);
  // A window outside the output, and a negative thread count, are errors.
  OIIO::ImageBuf outside;
  CHECK_FALSE(upscale(outside, src, options, OIIO::ROI(40, 60, 0, 5)));
  CHECK(outside.geterror().find("48x38 output") != std::string::npos);
  OIIO::ImageBuf threads;
  CHECK_FALSE(upscale(threads, src, options, {}, -1));
  CHECK(threads.has_error());
}

TEST_CASE("upscale: on a 30 degree step edge, variance DDT is closer to the analytic edge than bicubic") {
  // The scene is box-filtered at both resolutions, so HR is the true answer.
  const Scene& scene = find_scene("edge_30");
  const int w = 32, s = 4;
  const Image lr = render_scene(scene, w, w);
  const Image hr = render_scene(scene, w * s, w * s);
  UpscaleOptions opt;
  opt.cost = "variance";
  opt.render = Render::linear;  // the paper's surface
  const Image ddt = upscale(lr, w * s, w * s, opt);
  const Image bicubic = matlab_imresize_bicubic(lr, w * s, w * s);
  auto rmse = [&](const Image& img) {
    double sum = 0;
    for (std::size_t i = 0; i < hr.pixels.size(); ++i) sum += std::pow(double(img.pixels[i]) - hr.pixels[i], 2);
    return std::sqrt(sum / hr.pixels.size());
  };
  MESSAGE("edge_30 x4 RMSE: ddt-variance " << rmse(ddt) << ", bicubic " << rmse(bicubic));
  CHECK(rmse(ddt) < 0.9 * rmse(bicubic));
}

TEST_CASE("upscale: both render modes reproduce the samples exactly at scale 3") {
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0, 1);
  Image in(10, 8, 3);
  for (auto& v : in.pixels) v = u(rng);
  for (const Render render : {Render::cubic, Render::linear}) {
    CAPTURE(to_string(render));
    UpscaleOptions opt;
    opt.render = render;
    opt.model.kind = AcquisitionModel::Kind::point;
    const Image out = upscale(in, 30, 24, opt);
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 10; ++i)
        for (int c = 0; c < 3; ++c) REQUIRE(out.at(3 * i + 1, 3 * j + 1, c) == in.at(i, j, c));
  }
}

TEST_CASE("upscale: the cubic render reproduces a linear ramp, clamped outside the hull") {
  const int w = 12, h = 9;
  const Image in = test::sampled_image(w, h, 1, [](double x, double y, int) { return 0.2 + 0.03 * x - 0.02 * y; });
  for (double scale : {2.0, 3.7}) {
    const int ow = int(std::round(w * scale)), oh = int(std::round(h * scale));
    UpscaleOptions point;
    point.model.kind = AcquisitionModel::Kind::point;
    const Image out = upscale(in, ow, oh, point);
    double worst = 0;
    for (int Y = 0; Y < oh; ++Y)
      for (int X = 0; X < ow; ++X) {
        const double x = std::clamp((X + 0.5) * w / ow, 0.5, w - 0.5), y = std::clamp((Y + 0.5) * h / oh, 0.5, h - 0.5);
        worst = std::max(worst, std::abs(out.at(X, Y) - (0.2 + 0.03 * x - 0.02 * y)));
      }
    CHECK(worst < 1e-6);
  }
}

TEST_CASE("upscale: no ringing halos and no staircase along edges of the synthetic scenes") {
  // Overshoot: how far the output leaves the range of the input samples in
  // the 4x4 neighbourhood around each output pixel's position; bicubic and
  // Lanczos ring there, the default DDT render must not.
  const int w = 48, s = 4;
  for (const std::string name : {"edge_10", "edge_30", "edge_63", "disk", "strokes"}) {
    CAPTURE(name);
    const Image lr = render_scene(find_scene(name), w, w);
    const Image hr = render_scene(find_scene(name), w * s, w * s);
    UpscaleOptions point;  // the 3x3-input-range bound is the point model's
    point.model.kind = AcquisitionModel::Kind::point;
    const Image out = upscale(lr, w * s, w * s, point);
    const Image bicubic = matlab_imresize_bicubic(lr, w * s, w * s);
    auto overshoot = [&](const Image& img) {
      double worst = 0;
      for (int Y = 0; Y < w * s; ++Y)
        for (int X = 0; X < w * s; ++X) {
          const int cx = X / s, cy = Y / s;
          float lo = 1e9f, hi = -1e9f;
          for (int j = std::max(0, cy - 1); j <= std::min(w - 1, cy + 1); ++j)
            for (int i = std::max(0, cx - 1); i <= std::min(w - 1, cx + 1); ++i)
              lo = std::min(lo, lr.at(i, j)), hi = std::max(hi, lr.at(i, j));
          worst = std::max({worst, double(img.at(X, Y) - hi), double(lo - img.at(X, Y))});
        }
      return worst;
    };
    // Staircase: error against the true high-resolution scene, which a
    // jagged edge raises; the DDT edge must beat bicubic's.
    auto rmse = [&](const Image& img) {
      double sum = 0;
      for (std::size_t i = 0; i < hr.pixels.size(); ++i) sum += std::pow(double(img.pixels[i]) - hr.pixels[i], 2);
      return std::sqrt(sum / hr.pixels.size());
    };
    MESSAGE(name << ": overshoot ddt " << overshoot(out) << " bicubic " << overshoot(bicubic) << "; rmse ddt "
                 << rmse(out) << " bicubic " << rmse(bicubic));
    CHECK(overshoot(out) < 0.01);
    CHECK(overshoot(bicubic) > 0.02);
    CHECK(rmse(out) < rmse(bicubic));
  }
}
