// Footprints on one straight edge drawn as that edge (step_edges.hpp), and
// what the default upscale makes of straight edges it has never seen.
#include "consistency/step_edges.hpp"

#include "eval/edge_sharpness.hpp"
#include "eval/synthetic_scenes.hpp"
#include "pipeline/upscale.hpp"

#include "test_support.hpp"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace ddt;

namespace {

constexpr double kPi = std::numbers::pi;

// One straight step through (px, py) of the unit square, turned `degrees`
// clockwise from vertical, `low` behind and `high` ahead; channel c of an
// RGB version takes its own pair of levels.
Scene straight_edge(double degrees, double px, double py, int channels = 1) {
  const double t = degrees * kPi / 180.0, nx = std::cos(t), ny = std::sin(t);
  Scene s;
  s.name = "straight";
  s.channels = channels;
  s.background = [channels](double, double, float* out) {
    const float level[3] = {0.15f, 0.7f, 0.3f};
    for (int c = 0; c < channels; ++c) out[c] = level[c];
  };
  s.layers.push_back({[=](double x, double y) { return -(nx * (x - px) + ny * (y - py)); }, {0.85f, 0.2f, 0.35f}});
  s.step_edge = SceneStepEdge{px, py, nx, ny, 0.15f, 0.85f};
  return s;
}

double footprint_mean(const Image& out, int x, int y, int s, int c) {
  double sum = 0;
  for (int Y = y * s; Y < (y + 1) * s; ++Y)
    for (int X = x * s; X < (x + 1) * s; ++X) sum += out.at(X, Y, c);
  return sum / (s * s);
}

}  // namespace

TEST_CASE("rectangle_coverage: the exact share of a rectangle, against dense sampling") {
  for (double degrees : {0.0, 7.0, 30.0, 45.0, 80.0, 90.0, 135.0})
    for (double s : {-0.9, -0.4, -0.1, 0.0, 0.05, 0.3, 0.62})
      for (auto [w, h] : {std::pair{1.0, 1.0}, std::pair{0.1, 0.1}, std::pair{1.0, 0.5}}) {
        const double t = degrees * kPi / 180, nx = std::cos(t), ny = std::sin(t);
        const double d = s * std::max(w, h);  // the rectangle centred at 0, the line at n . p = -d
        const int n = 400;
        int inside = 0;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j) {
            const double x = ((i + 0.5) / n - 0.5) * w, y = ((j + 0.5) / n - 0.5) * h;
            inside += nx * x + ny * y + d > 0;
          }
        CAPTURE(degrees);
        CAPTURE(s);
        CHECK(rectangle_coverage(d, w * std::abs(nx), h * std::abs(ny)) ==
              doctest::Approx(double(inside) / (n * n)).epsilon(3e-3));
      }
  CHECK(rectangle_coverage(0.7, 1, 0) == 1);
  CHECK(rectangle_coverage(-0.5, 0.6, 0.4) == 0);
  CHECK(rectangle_coverage(0.1, 0.6, 0.4) == doctest::Approx(1 - rectangle_coverage(-0.1, 0.6, 0.4)));
}

TEST_CASE("render_step_edges: a box-filtered straight edge is redrawn as the truth, footprint means kept") {
  // Angles and offsets the standard scenes do not use.
  for (double degrees : {3.0, 17.0, 38.0, 52.0, 71.0, 98.0, 151.0}) {
    CAPTURE(degrees);
    const Scene scene = straight_edge(degrees, 0.437, 0.561, 3);
    const int w = 24, s = 6;
    const Image lr = render_scene(scene, w, w);
    const Image truth = render_scene(scene, w * s, w * s);
    Image out(w * s, w * s, 3);
    for (int Y = 0; Y < w * s; ++Y)  // a blurry stand-in whose footprint means are the input
      for (int X = 0; X < w * s; ++X)
        for (int c = 0; c < 3; ++c) out.at(X, Y, c) = lr.at(X / s, Y / s, c);
    const long long drawn = render_step_edges(out, lr);
    CHECK(drawn >= w / 2);
    double worst_mean = 0, worst_truth = 0;
    for (int y = 2; y < w - 2; ++y)
      for (int x = 2; x < w - 2; ++x)
        for (int c = 0; c < 3; ++c) {
          worst_mean = std::max(worst_mean, std::abs(footprint_mean(out, x, y, s, c) - lr.at(x, y, c)));
          for (int Y = y * s; Y < (y + 1) * s; ++Y)
            for (int X = x * s; X < (x + 1) * s; ++X)
              worst_truth = std::max(worst_truth, double(std::abs(out.at(X, Y, c) - truth.at(X, Y, c))));
        }
    CHECK(worst_mean < 1e-5);
    CHECK(worst_truth < 0.02);  // the scene's renderer is accurate to about 1e-3; the step is 0.7
  }
}

TEST_CASE("render_step_edges: an 8-bit edge with a code of noise is still drawn (its 5x5 pixels leave the 3x3 range "
          "by a code or two)") {
  for (double degrees : {17.0, 52.0, 98.0}) {
    CAPTURE(degrees);
    const Scene scene = straight_edge(degrees, 0.437, 0.561, 3);
    const int w = 24, s = 4;
    Image lr = render_scene(scene, w, w);
    for (int y = 0; y < w; ++y)  // a code up, down or none, then 8 bits, as a camera's file holds
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          const int noise = (x * 7 + y * 13 + c * 5) % 3 - 1;
          lr.at(x, y, c) = std::clamp(std::round(lr.at(x, y, c) * 255) + noise, 0.0f, 255.0f) / 255;
        }
    Image out(w * s, w * s, 3);
    for (int Y = 0; Y < w * s; ++Y)
      for (int X = 0; X < w * s; ++X)
        for (int c = 0; c < 3; ++c) out.at(X, Y, c) = lr.at(X / s, Y / s, c);
    CHECK(render_step_edges(out, lr) >= w / 2);
  }
}

TEST_CASE("render_step_edges: smooth gradients, thin lines, corners and noise are left alone") {
  const int w = 32, s = 4;
  for (const char* name : {"ramp", "smooth_waves", "thin_line", "checker_rotated"}) {
    CAPTURE(std::string(name));
    const Image lr = render_scene(find_scene(name), w, w);
    Image out(w * s, w * s, lr.channels, 0.5f);
    const Image before = out;
    const long long drawn = render_step_edges(out, lr);
    if (std::string(name) == "checker_rotated") {
      CHECK(drawn < w * w / 8);  // cell sides away from corners may pass, corners may not
    } else {
      CHECK(drawn == 0);
      CHECK(out.pixels == before.pixels);
    }
  }
  Image noise(w, w, 1);
  noise.pixels = test::random_values(noise.pixels.size(), 1, 4);
  Image out(w * s, w * s, 1, 0.5f);
  CHECK(render_step_edges(out, noise) == 0);
}

TEST_CASE("upscale: unseen straight edges at x10 rise within 0.5 input pixels and stay straight") {
  // The targets on the analytic edges, here on angles and
  // positions of its own: rise <= 0.5, wobble <= 0.02 input pixels,
  // overshoot <= 1 % of the step.
  for (double degrees : {0.0, 13.0, 41.0, 77.0, 90.0}) {
    CAPTURE(degrees);
    const Scene scene = straight_edge(degrees, 0.471, 0.523);
    const int w = 40, s = 10;
    const Image out = upscale(render_scene(scene, w, w), w * s, w * s);
    const SceneStepEdge& e = *scene.step_edge;
    const StepEdge edge{e.x * w * s, e.y * w * s, e.nx, e.ny, e.low, e.high};
    const EdgeSharpness m = measure_edge_sharpness(out, edge, s);
    REQUIRE(m.profiles > 10);
    CHECK(m.rise_width <= 0.5);
    CHECK(m.wobble <= 0.02);
    CHECK(m.overshoot <= 1.0);
    UpscaleOptions smooth;
    smooth.step_edges = false;
    const EdgeSharpness off = measure_edge_sharpness(upscale(render_scene(scene, w, w), w * s, w * s, smooth), edge, s);
    CHECK(m.rise_width < off.rise_width);
  }
}

TEST_CASE("upscale: low-contrast straight edges quantized to 8 bits are drawn sharp too") {
  // A step of 0.09 (23 code values): rounding to 8 bits errs by up to 5 %
  // of it, which the fit allows for as half a code value.
  for (double degrees : {8.0, 33.0, 61.0}) {
    CAPTURE(degrees);
    const Scene scene = straight_edge(degrees, 0.509, 0.488);
    const int w = 40, s = 10;
    Image lr = render_scene(scene, w, w);
    for (float& v : lr.pixels) v = std::round((0.45f + (v - 0.15f) * (0.09f / 0.7f)) * 255) / 255;
    const SceneStepEdge& e = *scene.step_edge;
    const StepEdge edge{e.x * w * s, e.y * w * s, e.nx, e.ny, 0.45, 0.54};
    const EdgeSharpness m = measure_edge_sharpness(upscale(lr, w * s, w * s), edge, s);
    REQUIRE(m.profiles > 10);
    MESSAGE("8-bit step 0.09 at " << degrees << " degrees, x10: rise " << m.rise_width << ", wobble " << m.wobble);
    CHECK(m.rise_width <= 0.5);
    CHECK(m.wobble <= 0.05);
  }
}

TEST_CASE("upscale: the default's output is the same on 1 and 2 threads") {
  const Image lr = render_scene(find_scene("colour_regions"), 40, 40);
  Image one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = upscale(lr, 280, 280);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = upscale(lr, 280, 280);
  }
  CHECK(one.pixels == two.pixels);
}
