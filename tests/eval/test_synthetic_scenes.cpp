#include "util/error.hpp"
#include "eval/synthetic_scenes.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <vector>

using namespace ddt;

namespace {

struct P2 {
  double x, y;
};

// Area of the part of the polygon where nx x + ny y > c: Sutherland-Hodgman
// against one half-plane, then the shoelace formula. Independent of the
// renderer's closed-form coverage.
double clipped_area(const std::vector<P2>& poly, double nx, double ny, double c) {
  std::vector<P2> out;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const P2 a = poly[k], b = poly[(k + 1) % poly.size()];
    const double fa = nx * a.x + ny * a.y - c, fb = nx * b.x + ny * b.y - c;
    if (fa > 0) out.push_back(a);
    if ((fa > 0) != (fb > 0)) {
      const double t = fa / (fa - fb);
      out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  double twice = 0;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const P2 a = out[k], b = out[(k + 1) % out.size()];
    twice += a.x * b.y - b.x * a.y;
  }
  return 0.5 * std::abs(twice);
}

double image_mean(const Image& img, int channel) {
  double sum = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) sum += img.at(x, y, channel);
  return sum / static_cast<double>(img.pixel_count());
}

// Each output pixel the mean of a 2x2 block.
Image downsample_2x2(const Image& img) {
  Image out(img.width / 2, img.height / 2, img.channels);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < img.channels; ++c)
        out.at(x, y, c) = 0.25f * (img.at(2 * x, 2 * y, c) + img.at(2 * x + 1, 2 * y, c) +
                                   img.at(2 * x, 2 * y + 1, c) + img.at(2 * x + 1, 2 * y + 1, c));
  return out;
}

float max_abs_difference(const Image& a, const Image& b) {
  float worst = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i)
    worst = std::max(worst, std::abs(a.pixels[i] - b.pixels[i]));
  return worst;
}

}  // namespace

TEST_CASE("standard_scenes: unique names, grey or RGB, values in 0..1") {
  const std::vector<Scene> scenes = standard_scenes();
  CHECK(scenes.size() >= 10);
  CHECK(scenes.size() <= 12);
  std::set<std::string> names;
  int colour = 0;
  for (const Scene& s : scenes) {
    INFO(s.name);
    CHECK(names.insert(s.name).second);
    CHECK_FALSE(s.description.empty());
    CHECK((s.channels == 1 || s.channels == 3));
    colour += s.channels == 3;
    const Image img = render_scene(s, 40, 24);
    REQUIRE(img.width == 40);
    REQUIRE(img.height == 24);
    REQUIRE(img.channels == s.channels);
    const auto [lo, hi] = std::minmax_element(img.pixels.begin(), img.pixels.end());
    CHECK(*lo >= 0.0f);
    CHECK(*hi <= 1.0f);
  }
  CHECK(colour >= 1);
}

TEST_CASE("standard_scenes: layer distance bounds are 1-Lipschitz") {
  // The renderer skips a cell when |sd(centre)| exceeds its half-diagonal;
  // a bound steeper than 1 would let it miss a boundary.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0), step(-0.03, 0.03);
  for (const Scene& s : standard_scenes()) {
    INFO(s.name);
    for (const SceneLayer& layer : s.layers) {
      double worst = 0;
      for (int k = 0; k < 20000; ++k) {
        const double x = unit(rng), y = unit(rng), dx = step(rng), dy = step(rng);
        const double ratio = std::abs(layer.sd(x + dx, y + dy) - layer.sd(x, y)) / std::hypot(dx, dy);
        worst = std::max(worst, ratio);
      }
      CHECK(worst <= 1.0 + 1e-9);
    }
  }
}

TEST_CASE("render_scene: step edge pixels equal the exact area coverage") {
  // Each edge scene: 0.2 + 0.6 * (area of the pixel on the bright side of the
  // line through (0.52, 0.5) with normal (cos t, sin t)).
  const std::array<int, 5> angles = {0, 10, 30, 45, 63};
  for (int degrees : angles) {
    const std::string name = (degrees < 10 ? "edge_0" : "edge_") + std::to_string(degrees);
    const Scene& scene = find_scene(name);
    const double t = degrees * std::numbers::pi / 180.0;
    const double nx = std::cos(t), ny = std::sin(t), c = nx * 0.52 + ny * 0.5;
    for (auto [w, h] : {std::pair{64, 64}, std::pair{37, 23}}) {
      INFO(name << " at " << w << "x" << h);
      const Image img = render_scene(scene, w, h);
      int crossed = 0;
      double worst = 0;
      for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
          const double x0 = double(i) / w, x1 = double(i + 1) / w;
          const double y0 = double(j) / h, y1 = double(j + 1) / h;
          const double area = clipped_area({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, nx, ny, c);
          const double fraction = area * w * h;
          crossed += fraction > 1e-9 && fraction < 1 - 1e-9;
          worst = std::max(worst, std::abs(img.at(i, j) - (0.2 + 0.6 * fraction)));
        }
      }
      CHECK(crossed >= std::min(w, h));
      CHECK(worst <= 1e-3);
    }
  }
}

TEST_CASE("render_scene: ramp pixels equal the ramp at the pixel centre") {
  // The box average of a linear function is its value at the box centre.
  const Scene& ramp = find_scene("ramp");
  for (auto [w, h] : {std::pair{64, 64}, std::pair{50, 30}}) {
    INFO(w << "x" << h);
    const Image img = render_scene(ramp, w, h);
    double worst = 0;
    for (int j = 0; j < h; ++j) {
      for (int i = 0; i < w; ++i) {
        float centre;
        ramp.field((i + 0.5) / w, (j + 0.5) / h, &centre);
        worst = std::max(worst, double(std::abs(img.at(i, j) - centre)));
      }
    }
    CHECK(worst <= 1e-6);
  }
}

TEST_CASE("render_scene: image mean does not depend on the resolution") {
  // Box filtering preserves the integral, so every rendering has the same mean.
  for (const Scene& s : standard_scenes()) {
    INFO(s.name);
    const Image small = render_scene(s, 32, 32), large = render_scene(s, 256, 256);
    for (int c = 0; c < s.channels; ++c) CHECK(std::abs(image_mean(small, c) - image_mean(large, c)) <= 1e-3);
  }
}

TEST_CASE("render_scene: 2x2 box downsampling of 2W x 2H equals W x H") {
  for (const Scene& s : standard_scenes()) {
    INFO(s.name);
    const Image low = render_scene(s, 48, 40);
    const Image high = downsample_2x2(render_scene(s, 96, 80));
    CHECK(max_abs_difference(low, high) <= 1e-3);
  }
}

TEST_CASE("render_scene: agrees with naive supersampling of the field") {
  // The naive renderer beside the fast one: 48 x 48 midpoint samples per
  // pixel. Its own error reaches 0.6 / 96 on axis-parallel edges; a missed
  // feature (the thin line is 1/12 pixel wide here) is worth 0.05.
  constexpr int kSize = 16, kSamples = 48;
  for (const Scene& s : standard_scenes()) {
    INFO(s.name);
    const Image img = render_scene(s, kSize, kSize);
    float worst = 0;
    float value[3];
    for (int j = 0; j < kSize; ++j) {
      for (int i = 0; i < kSize; ++i) {
        double sum[3] = {0, 0, 0};
        for (int b = 0; b < kSamples; ++b)
          for (int a = 0; a < kSamples; ++a) {
            s.field((i + (a + 0.5) / kSamples) / kSize, (j + (b + 0.5) / kSamples) / kSize, value);
            for (int c = 0; c < s.channels; ++c) sum[c] += value[c];
          }
        for (int c = 0; c < s.channels; ++c)
          worst = std::max(worst, std::abs(img.at(i, j, c) - float(sum[c] / (kSamples * kSamples))));
      }
    }
    CHECK(worst <= 8e-3);
  }
}

TEST_CASE("find_scene: known name found, unknown name lists the valid ones") {
  CHECK(find_scene("disk").name == "disk");
  CHECK(&find_scene("disk") == &find_scene("disk"));
  std::string message;
  try {
    find_scene("no_such_scene");
  } catch (const Error& e) {
    message = e.what();
  }
  CHECK(message.find("no_such_scene") != std::string::npos);
  for (const Scene& s : standard_scenes()) CHECK(message.find(s.name) != std::string::npos);
}

TEST_CASE("render_scene: rejects an empty size") {
  CHECK_THROWS_AS(render_scene(find_scene("disk"), 0, 8), Error);
  CHECK_THROWS_AS(render_scene(find_scene("disk"), 8, -1), Error);
}
