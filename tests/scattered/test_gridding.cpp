#include "util/error.hpp"
#include "scattered/gridding.hpp"
#include "io/image_io.hpp"

#include <OpenImageIO/imageio.h>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>

using namespace ddt;

namespace {

double radical_inverse(int i, int base) {
  double f = 1, r = 0;
  for (; i > 0; i /= base) {
    f /= base;
    r += f * (i % base);
  }
  return r;
}

// n Halton points (bases 2, 3) in [0, 1]^2 plus its four corners, so the
// hull is the whole square; deterministic on every platform.
std::vector<Point2> halton_square(int n) {
  std::vector<Point2> p{{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  for (int i = 1; i <= n; ++i) p.push_back({radical_inverse(i, 2), radical_inverse(i, 3)});
  return p;
}

std::vector<float> sample(const std::vector<Point2>& p, const std::function<double(double, double)>& f) {
  std::vector<float> v;
  for (const Point2& q : p) v.push_back(static_cast<float>(f(q.x, q.y)));
  return v;
}

// RMSE of channel 0 against f at the pixel centres of the grid convention.
double rmse(const Image& img, const GridBounds& b, const std::function<double(double, double)>& f) {
  double sum = 0;
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i < img.width; ++i) {
      const double x = b.xmin + (i + 0.5) * (b.xmax - b.xmin) / img.width;
      const double y = b.ymax - (j + 0.5) * (b.ymax - b.ymin) / img.height;
      const double d = img.at(i, j) - f(x, y);
      sum += d * d;
    }
  return std::sqrt(sum / static_cast<double>(img.pixel_count()));
}

// A fault: a 30 degree line with a unit step across it, on a gentle slope.
double step(double x, double y) { return 0.2 * x + (y > 0.3 + 0.58 * x ? 1.0 : 0.0); }

}  // namespace

TEST_CASE("grid_points: north-up pixel centres, a plane reproduced exactly") {
  // Pixel (i, j) samples x = (i + 0.5) * 2 / 2, y = 2 - (j + 0.5) * 2 / 2.
  const std::vector<Point2> p{{0, 0}, {2, 0}, {0, 2}, {2, 2}};
  auto plane = [](double x, double y) { return x + 10 * y; };
  GridOptions o;
  o.width = o.height = 2;
  const Image img = grid_points(p, sample(p, plane), 1, o);
  CHECK(img.at(0, 0) == 15.5f);  // (0.5, 1.5): top left is north-west
  CHECK(img.at(1, 0) == 16.5f);
  CHECK(img.at(0, 1) == 5.5f);   // (0.5, 0.5)
  CHECK(img.at(1, 1) == 6.5f);
}

TEST_CASE("grid_points: scattered samples of a plane give the plane inside the hull, NaN outside") {
  // Points inside the triangle x >= 0, y >= 0, x + y <= 1 (and on its sides).
  std::vector<Point2> p{{0, 0}, {1, 0}, {0, 1}};
  for (int i = 1; i <= 60; ++i) {
    const double u = radical_inverse(i, 2), v = radical_inverse(i, 3);
    p.push_back(u + v <= 1 ? Point2{u, v} : Point2{1 - u, 1 - v});
  }
  auto plane = [](double x, double y) { return 3.0 - 2.0 * x + 0.5 * y; };
  GridOptions o;
  o.width = 40;
  o.height = 30;
  o.bounds = GridBounds{0, 0, 1, 1};
  GridStats st;
  const Image img = grid_points(p, sample(p, plane), 1, o, &st);
  long long inside = 0;
  for (int j = 0; j < o.height; ++j)
    for (int i = 0; i < o.width; ++i) {
      const double x = (i + 0.5) / o.width, y = 1 - (j + 0.5) / o.height;
      const float v = img.at(i, j);
      if (x + y < 1 - 1e-9) {
        REQUIRE(std::isfinite(v));
        CHECK(v == doctest::Approx(plane(x, y)).epsilon(1e-6));
        ++inside;
      } else if (x + y > 1 + 1e-9) {
        CHECK(std::isnan(v));
      }
    }
  CHECK(inside == st.inside_pixels);  // no centre lies on the hypotenuse for 40x30
  CHECK(st.nodata_pixels == 40 * 30 - inside);
}

TEST_CASE("grid_points: on a step field the step-aligned DDT mesh beats plain Delaunay") {
  const std::vector<Point2> p = halton_square(400);
  const std::vector<float> v = sample(p, step);
  GridOptions o;
  o.width = o.height = 128;
  o.cost = "variance";  // the cost that aligns triangles with steps (docs/scattered.md)
  GridStats st;
  const Image ddt_img = grid_points(p, v, 1, o, &st);
  o.optimize = false;
  const Image delaunay_img = grid_points(p, v, 1, o);
  const GridBounds b{0, 0, 1, 1};
  const double e_ddt = rmse(ddt_img, b, step), e_delaunay = rmse(delaunay_img, b, step);
  MESSAGE("step RMSE: DDT " << e_ddt << ", Delaunay " << e_delaunay << ", " << st.flips << " flips");
  CHECK(st.flips > 0);
  CHECK(st.cost_after < st.cost_before);
  CHECK(e_ddt < 0.8 * e_delaunay);
}

TEST_CASE("grid_points: the default cost beats plain Delaunay on a step and a ridge, not worse on a smooth field") {
  // docs/scattered.md, "Which cost": one default for all inputs. The fields
  // of bench/grid_fields.cpp (fault, tent ridge, Franke's function), here
  // on Halton points of the unit square.
  auto fault = [](double x, double y) { return 0.3 * x + 0.2 * y + (y > 0.3 + 0.6 * x ? 1.0 : 0.0); };
  auto ridge = [](double x, double y) { return std::max(0.0, 1.0 - std::abs(0.8 * x + 0.6 * y - 0.7) / 0.2); };
  auto franke = [](double x, double y) {
    const double a = 9 * x, b = 9 * y;
    return 0.75 * std::exp(-((a - 2) * (a - 2) + (b - 2) * (b - 2)) / 4) +
           0.75 * std::exp(-(a + 1) * (a + 1) / 49 - (b + 1) / 10) +
           0.5 * std::exp(-((a - 7) * (a - 7) + (b - 3) * (b - 3)) / 4) -
           0.2 * std::exp(-(a - 4) * (a - 4) - (b - 7) * (b - 7));
  };
  CHECK(GridOptions{}.cost == "jnd-edge");
  const std::vector<Point2> p = halton_square(1000);
  const GridBounds b{0, 0, 1, 1};
  struct Case {
    const char* name;
    std::function<double(double, double)> f;
    double at_most;  // RMSE of DDT / RMSE of Delaunay
  };
  for (const Case& c : {Case{"fault", fault, 0.97}, Case{"ridge", ridge, 0.97}, Case{"smooth", franke, 1.0}}) {
    const std::vector<float> v = sample(p, c.f);
    GridOptions o;
    o.width = o.height = 128;
    GridStats st;
    const Image ddt_img = grid_points(p, v, 1, o, &st);
    o.optimize = false;
    const Image delaunay_img = grid_points(p, v, 1, o);
    const double e_ddt = rmse(ddt_img, b, c.f), e_delaunay = rmse(delaunay_img, b, c.f);
    MESSAGE(std::string(c.name) << " RMSE: DDT " << e_ddt << ", Delaunay " << e_delaunay << ", " << st.flips
                                << " flips");
    CHECK(st.flips > 0);
    CHECK(e_ddt <= c.at_most * e_delaunay);
  }
}

TEST_CASE("grid_points: every optimizer of the image path, reproducible, a bad one refused") {
  const std::vector<Point2> p = halton_square(300);
  const std::vector<float> v = sample(p, step);
  GridOptions o;
  o.width = o.height = 32;
  o.cost = "variance";
  GridStats lawson, lookahead, anneal, anneal_again;
  const Image a = grid_points(p, v, 1, o, &lawson);
  o.optimizer = Optimizer::lookahead;
  grid_points(p, v, 1, o, &lookahead);
  CHECK(lookahead.cost_after <= lawson.cost_after);  // look-ahead starts from Lawson's optimum
  o.optimizer = Optimizer::anneal;
  o.anneal.seed = 3;
  const Image b = grid_points(p, v, 1, o, &anneal);
  const Image c = grid_points(p, v, 1, o, &anneal_again);
  CHECK(anneal.flips > lawson.flips);
  CHECK(anneal.cost_after == anneal_again.cost_after);
  CHECK(std::equal(b.pixels.begin(), b.pixels.end(), c.pixels.begin(), c.pixels.end(),
                   [](float x, float y) { return x == y || (std::isnan(x) && std::isnan(y)); }));
  CHECK_THROWS_AS(optimizer_by_name("genetic"), Error);
  o.optimizer = Optimizer::anneal;
  o.anneal.cooling = 1.0;
  CHECK_THROWS_AS(grid_points(p, v, 1, o), Error);
}

TEST_CASE("grid_points: samples on the hull at pixel centres are kept (an XYZ grid at its own resolution)") {
  // A 5 x 4 grid of cell centres, gridded over its cell edges: every pixel
  // centre is a sample, the outer ones on the hull.
  std::vector<Point2> p;
  std::vector<float> v;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i) {
      p.push_back({100 + 10 * (i + 0.5), 50 - 10 * (j + 0.5)});
      v.push_back(static_cast<float>(i + 10 * j));
    }
  GridOptions o;
  o.width = 5;
  o.height = 4;
  o.bounds = GridBounds{100, 10, 150, 50};
  GridStats st;
  const Image img = grid_points(p, v, 1, o, &st);
  CHECK(st.nodata_pixels == 0);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i) CHECK(img.at(i, j) == static_cast<float>(i + 10 * j));
}

TEST_CASE("grid_points: alpha channel, --nodata value, several channels on one mesh") {
  const std::vector<Point2> p{{0, 0}, {1, 0}, {0, 1}};
  const std::vector<float> v{0, 10, 1, 11, 2, 12};
  GridOptions o;
  o.width = o.height = 4;
  o.bounds = GridBounds{0, 0, 1, 1};
  o.nodata = 0;
  o.alpha = true;
  const Image img = grid_points(p, v, 2, o);
  REQUIRE(img.channels == 3);
  CHECK(img.at(0, 3, 2) == 1.0f);  // (0.125, 0.125): inside
  CHECK(img.at(0, 3, 0) == doctest::Approx(0.125 * 1 + 0.125 * 2 + 0.75 * 0));
  CHECK(img.at(0, 3, 1) == doctest::Approx(10.375));
  CHECK(img.at(3, 0, 2) == 0.0f);  // (0.875, 0.875): outside
  CHECK(img.at(3, 0, 0) == 0.0f);
  o.alpha = false;
  o.nodata = 1.0f;  // the alpha must not pick this up
  const Image plain = grid_points(p, v, 2, o);
  CHECK(plain.channels == 2);
  CHECK(plain.at(3, 0, 0) == 1.0f);
}

TEST_CASE("grid_points: NaN no-data survives an EXR round trip") {
  const std::vector<Point2> p{{0, 0}, {1, 0}, {0, 1}};
  GridOptions o;
  o.width = o.height = 8;
  const Image img = grid_points(p, {1, 2, 3}, 1, o);
  const auto path = std::filesystem::temp_directory_path() / "ddtscale_test_grid_nan.exr";
  write_image(path.string(), img, SampleFormat::float32);
  auto in = OIIO::ImageInput::open(path.string());
  REQUIRE(in);
  std::vector<float> px(64);
  REQUIRE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, px.data()));
  in->close();
  std::filesystem::remove(path);
  CHECK(std::isnan(px[7]));       // top right: outside
  CHECK(std::isfinite(px[7 * 8]));  // bottom left: inside
}

TEST_CASE("grid_points: bad input is a ddt::Error") {
  const std::vector<Point2> line{{0, 0}, {1, 1}, {2, 2}};
  GridOptions o;
  o.width = o.height = 4;
  CHECK_THROWS_WITH_AS(grid_points(line, {0, 1, 2}, 1, o),
                       "the points span no area: need at least three points not on one line (got 3 distinct positions)",
                       Error);
  const std::vector<Point2> tri{{0, 0}, {1, 0}, {0, 1}};
  o.bounds = GridBounds{0, 0, 0, 1};
  CHECK_THROWS_AS(grid_points(tri, {0, 1, 2}, 1, o), Error);
  o.bounds.reset();
  o.cost_channel = 1;
  CHECK_THROWS_WITH_AS(grid_points(tri, {0, 1, 2}, 1, o), "--cost-channel 2: the points have 1 value channel", Error);
  o.cost_channel = cost_channel_luma;
  CHECK_THROWS_AS(grid_points(tri, {0, 1, 2}, 1, o), Error);
  o.cost_channel = cost_channel_sum;
  o.width = 0;
  CHECK_THROWS_AS(grid_points(tri, {0, 1, 2}, 1, o), Error);
}

TEST_CASE("grid_points: huge and tiny coordinates: a similar copy grids alike, or is refused") {
  // Uniform scaling and translation of the positions leave the Delaunay
  // mesh, and the flips of a cost whose total scales uniformly with them
  // (variance: area times the values' variance), unchanged; so the grid's
  // values at the corresponding pixel centres are the same.
  const std::vector<Point2> unit = halton_square(40);
  const std::vector<float> v = sample(unit, [](double x, double y) { return std::sin(4 * x) + (y > 0.5 ? 1 : 0); });
  auto moved = [&](double scale, double offset) {
    std::vector<Point2> p;
    for (const Point2& q : unit) p.push_back({offset + scale * q.x, offset + scale * q.y});
    return p;
  };
  GridOptions o;
  o.width = o.height = 24;
  o.cost = "variance";
  for (const bool optimize : {false, true}) {
    o.optimize = optimize;
    const Image reference = grid_points(unit, v, 1, o);
    const std::vector<std::pair<double, double>> similar =
        optimize ? std::vector<std::pair<double, double>>{{1e150, 0}, {1e-150, 0}, {1e140, 1e150}, {1e-140, 1e-130}}
                 : std::vector<std::pair<double, double>>{{1e306, 0}, {5e306, -5e306}, {1e290, 1e300}, {1e-300, 0}};
    for (const auto& [scale, offset] : similar) {
      const Image out = grid_points(moved(scale, offset), v, 1, o);
      CAPTURE(optimize);
      CAPTURE(scale);
      CAPTURE(offset);
      float worst = 0;
      for (std::size_t i = 0; i < out.pixels.size(); ++i)
        worst = std::max(worst, std::abs(out.pixels[i] - reference.pixels[i]));
      CHECK(worst < 1e-4f);
    }
  }
  o.optimize = false;
  CHECK_THROWS_AS(grid_points(moved(1e308, 0), v, 1, o), Error);  // the render's sums overflow
  o.optimize = true;
  CHECK_THROWS_AS(grid_points(moved(1e155, 0), v, 1, o), Error);  // the costs' products overflow
  CHECK_THROWS_AS(grid_points(moved(1e-160, 0), v, 1, o), Error);  // ... or underflow
  o.bounds = GridBounds{-1e308, 0, 1e308, 1};
  CHECK_THROWS_AS(grid_points(unit, v, 1, o), Error);
}
