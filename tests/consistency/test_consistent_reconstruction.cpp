// The acquisition models and the consistent reconstruction
// (acquisition_model.hpp, consistent_reconstruction.hpp).
#include "consistency/acquisition_model.hpp"
#include "consistency/consistent_reconstruction.hpp"
#include "eval/edge_sharpness.hpp"
#include "util/error.hpp"
#include "eval/synthetic_scenes.hpp"
#include "image/cubic_surface.hpp"
#include "image/rasterizer.hpp"
#include "pipeline/upscale.hpp"

#include "test_support.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <string>

using namespace ddt;

namespace {

Image noise_image(int w, int h, int c, unsigned seed) {
  Image img(w, h, c);
  img.pixels = test::random_values(img.pixels.size(), 1, seed);
  return img;
}

double max_difference(const Image& a, const Image& b) {
  double m = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) m = std::max(m, std::abs(double(a.pixels[i]) - b.pixels[i]));
  return m;
}

}  // namespace

TEST_CASE("parse_acquisition_model: the four forms, and one-line errors for the rest") {
  CHECK(parse_acquisition_model("box").kind == AcquisitionModel::Kind::box);
  CHECK(parse_acquisition_model("point").kind == AcquisitionModel::Kind::point);
  CHECK(parse_acquisition_model("bicubic").kind == AcquisitionModel::Kind::bicubic);
  const AcquisitionModel g = parse_acquisition_model("gauss:0.7");
  CHECK(g.kind == AcquisitionModel::Kind::gauss);
  CHECK(g.sigma == doctest::Approx(0.7));
  CHECK(to_string(g) == "gauss:0.7");
  for (const char* bad : {"", "gauss", "gauss:", "gauss:-1", "gauss:0", "gauss:nan", "gauss:1x", "boxy", "Box"})
    CHECK_THROWS_AS(parse_acquisition_model(bad), Error);
}

TEST_CASE("axis_weights: every input pixel's weights sum to 1, box weights are the exact overlaps") {
  for (const char* name : {"box", "gauss:0.5", "bicubic"})
    for (auto [n, m] : {std::pair{7, 21}, std::pair{7, 16}, std::pair{10, 25}, std::pair{5, 5}}) {
      const AxisWeights w = axis_weights(parse_acquisition_model(name), n, m);
      std::vector<double> sum(n, 0.0);
      for (int X = 0; X < m; ++X)
        for (int k = w.first[X]; k < w.first[X + 1]; ++k) sum[w.pixel[k]] += w.weight[k];
      for (double s : sum) CHECK(s == doctest::Approx(1.0).epsilon(1e-12));
    }
  // n = 2, m = 3: output pixels cover [0, 2/3), [2/3, 4/3), [4/3, 2).
  const AxisWeights w = axis_weights(parse_acquisition_model("box"), 2, 3);
  REQUIRE(w.first == std::vector<int>{0, 1, 3, 4});
  CHECK(w.weight[0] == doctest::Approx(2.0 / 3));
  CHECK(w.weight[1] == doctest::Approx(1.0 / 3));
  CHECK(w.weight[2] == doctest::Approx(1.0 / 3));
}

TEST_CASE("Acquisition: every channel count, one weight a column or several, is the weighted sum of the output") {
  // The reference: each input pixel sums its output rows' weighted column
  // sums, in output order (the order the acquisition adds them, so equal bits).
  for (const char* name : {"box", "gauss:0.6"})
    for (int C : {1, 2, 3, 4})
      for (auto [w, h, ow, oh] : {std::array{8, 6, 32, 24}, std::array{8, 6, 24, 18}, std::array{9, 7, 20, 15}}) {
        CAPTURE(name);
        CAPTURE(C);
        CAPTURE(ow);
        const AcquisitionModel model = parse_acquisition_model(name);
        const Image out = noise_image(ow, oh, C, 11 + C);
        const AxisWeights wx = axis_weights(model, w, ow);
        const auto by_row = by_input_pixel(axis_weights(model, h, oh), h);
        std::vector<double> values;
        Acquisition(model, w, h, ow, oh).apply(out, 0, 0, h, values);
        REQUIRE(values.size() == static_cast<std::size_t>(w) * h * C);
        for (int jy = 0; jy < h; ++jy)
          for (int jx = 0; jx < w; ++jx)
            for (int c = 0; c < C; ++c) {
              double expected = 0;
              for (const auto& [Y, wy] : by_row[jy]) {
                double row = 0;
                for (int X = 0; X < ow; ++X)
                  for (int k = wx.first[X]; k < wx.first[X + 1]; ++k)
                    if (wx.pixel[k] == jx) row += wx.weight[k] * out.at(X, Y, c);
                expected += wy * row;
              }
              CHECK(values[(static_cast<std::size_t>(jy) * w + jx) * C + c] == expected);
            }
      }
}

TEST_CASE("Acquisition: rows of input from the output rows they read equal the whole acquisition") {
  const Image out = noise_image(37, 29, 2, 8);
  for (const char* name : {"box", "gauss:0.6", "bicubic"})
    for (auto [w, h] : {std::pair{9, 7}, std::pair{37, 29}, std::pair{12, 10}}) {
      CAPTURE(name);
      CAPTURE(w);
      const AcquisitionModel model = parse_acquisition_model(name);
      const Image whole = apply_acquisition(model, out, w, h);
      const Acquisition acquisition(model, w, h, out.width, out.height);
      const int first = h / 3, end = h - h / 4;
      const auto [lo, hi] = acquisition.rows_read(first, end);
      REQUIRE(lo < hi);
      Image rows(out.width, hi - lo, 2);
      std::copy(out.pixels.begin() + static_cast<std::ptrdiff_t>(out.index(0, lo)),
                out.pixels.begin() + static_cast<std::ptrdiff_t>(out.index(0, hi)), rows.pixels.begin());
      std::vector<double> part;
      acquisition.apply(rows, lo, first, end, part);
      REQUIRE(part.size() == static_cast<std::size_t>(w) * (end - first) * 2);
      for (std::size_t i = 0; i < part.size(); ++i)
        CHECK(static_cast<float>(part[i]) == whole.pixels[whole.index(0, first) + i]);
      // a row it reads missing is an error, not a wrong value
      if (lo + 1 < hi) {
        Image fewer(out.width, hi - lo - 1, 2);
        CHECK_THROWS_AS(acquisition.apply(fewer, lo + 1, first, end, part), Error);
      }
    }
}

namespace {

// A smooth image with edges, inside (0.1, 0.9): no clipping anywhere.
Image smooth_test_image(int w, int h, int channels) {
  return test::sampled_image(w, h, channels, [](double x, double y, int c) {
    const double edge = x + 0.6 * y > 9 ? 0.35 : 0.0;
    return 0.2 + edge + 0.15 * std::sin(0.7 * x + 0.3 * c) * std::cos(0.45 * y);
  });
}

}  // namespace

TEST_CASE("make_consistent: the output's footprint averages reproduce the input, any scale and model") {
  const Image in = smooth_test_image(17, 13, 3);
  for (const char* model : {"box", "gauss:0.5", "bicubic"})
    for (auto [ow, oh] : {std::pair{68, 52}, std::pair{51, 39}, std::pair{40, 31}, std::pair{170, 130}}) {
      CAPTURE(model);
      CAPTURE(ow);
      for (const Render render : {Render::cubic, Render::linear}) {
        CAPTURE(to_string(render));
        UpscaleOptions options;
        options.render = render;
        options.model = parse_acquisition_model(model);
        UpscaleStats stats;
        const Image out = upscale(in, ow, oh, options, &stats);
        const Image back = apply_acquisition(options.model, out, in.width, in.height);
        CHECK(max_difference(back, in) < 1e-4);
        CHECK(stats.consistency_residual < 1e-5);
      }
    }
}

TEST_CASE("make_consistent: noise flips a lot, and the footprint averages are still the input") {
  Image in = noise_image(24, 20, 1, 3);
  for (float& v : in.pixels) v = 0.2f + 0.6f * v;
  UpscaleStats stats;
  const Image out = upscale(in, 96, 80, {}, &stats);
  CHECK(stats.flips > 50);
  CHECK(max_difference(apply_acquisition(AcquisitionModel{}, out, 24, 20), in) < 1e-4);
}

TEST_CASE("make_consistent: a linear ramp is reproduced exactly away from the border") {
  // The box average of a linear function is its centre value: the ramp is
  // already consistent inside at integer scales; only the clamped rim needs
  // a correction, which decays within a few pixels of the border. At a
  // non-integer scale the output pixels cut by a footprint's side count by
  // area, with their centres off the part inside: the discrete average of
  // the sampled ramp is off by a fraction of slope / scale, and the
  // correction moves the ramp by about that.
  const int w = 24, h = 20;
  const Image in = test::sampled_image(w, h, 1, [](double x, double y, int) { return 0.2 + 0.02 * x - 0.015 * y; });
  for (double scale : {3.0, 2.6}) {
    const int ow = int(std::round(w * scale)), oh = int(std::round(h * scale));
    const Image out = upscale(in, ow, oh);
    double worst = 0;
    for (int Y = 0; Y < oh; ++Y)
      for (int X = 0; X < ow; ++X) {
        const double x = (X + 0.5) * w / ow, y = (Y + 0.5) * h / oh;
        if (x < 7 || y < 7 || x > w - 7 || y > h - 7) continue;
        worst = std::max(worst, std::abs(out.at(X, Y) - (0.2 + 0.02 * x - 0.015 * y)));
      }
    CAPTURE(scale);
    CHECK(worst < (scale == 3.0 ? 1e-4 : 0.2 * 0.02 / scale));
    CHECK(max_difference(apply_acquisition(AcquisitionModel{}, out, w, h), in) < 1e-4);
  }
}

TEST_CASE("make_consistent: degenerate shapes (1x1, a row, a column) are consistent too") {
  for (auto [w, h] : {std::pair{1, 1}, std::pair{7, 1}, std::pair{1, 7}, std::pair{2, 2}}) {
    const Image in = test::sampled_image(w, h, 1, [](double x, double y, int) { return 0.3 + 0.05 * x + 0.04 * y; });
    const Image out = upscale(in, w * 3, h * 3);
    CHECK(max_difference(apply_acquisition(AcquisitionModel{}, out, w, h), in) < 1e-4);
  }
}

TEST_CASE("upscale: --model point is the plain interpolation, box differs from it only by the correction") {
  const Image in = smooth_test_image(12, 10, 1);
  UpscaleOptions point;
  point.model.kind = AcquisitionModel::Kind::point;
  UpscaleStats stats;
  const Image plain = upscale(in, 36, 30, point, &stats);
  CHECK(stats.consistency_mesh_steps == 0);
  CHECK(stats.seconds_consistency == 0);
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 12; ++i) CHECK(plain.at(3 * i + 1, 3 * j + 1) == in.at(i, j));
  const Image consistent = upscale(in, 36, 30);
  CHECK(max_difference(plain, consistent) > 1e-3);
  CHECK(max_difference(plain, consistent) < 0.35);  // the image's one edge is a step of 0.35
}

TEST_CASE("upscale: the default leaves the truth's range by at most 1 % of the step beside edges") {
  // The bound against the truth: a consistent reconstruction must
  // darken thin lines below any input pixel, so the 3x3-input-range bound
  // of --model point does not apply; the true scene's range near each pixel
  // does. Bicubic and Lanczos fail it beside every edge (test_edge_sharpness).
  for (const char* name : {"edge_10", "edge_30", "edge_63", "disk", "strokes", "thin_line"})
    for (int s : {4, 10}) {
      CAPTURE(std::string(name));
      CAPTURE(s);
      const Scene& scene = find_scene(name);
      const int w = 32;
      const Image lr = render_scene(scene, w, w);
      const Image hr = render_scene(scene, w * s, w * s);
      const Image out = upscale(lr, w * s, w * s);
      TruthHaloOptions halo;
      halo.shave = s;
      CHECK(truth_halo(out, hr, s, halo) <= 0.01);
    }
}

TEST_CASE("upscale: the default's edges rise faster than --model point's, without overshoot") {
  const Scene& scene = find_scene("edge_30");
  const int w = 48, s = 10;
  const Image lr = render_scene(scene, w, w);
  UpscaleOptions point;
  point.model.kind = AcquisitionModel::Kind::point;
  const SceneStepEdge& e = *scene.step_edge;
  const StepEdge edge{e.x * w * s, e.y * w * s, e.nx, e.ny, e.low, e.high};  // a square image: the normal stays
  const EdgeSharpness consistent = measure_edge_sharpness(upscale(lr, w * s, w * s), edge, s);
  const EdgeSharpness plain = measure_edge_sharpness(upscale(lr, w * s, w * s, point), edge, s);
  MESSAGE("edge_30 x10 rise: box " << consistent.rise_width << ", point " << plain.rise_width);
  CHECK(consistent.rise_width < 0.7 * plain.rise_width);
  CHECK(consistent.rise_width < 0.6);
  CHECK(consistent.overshoot < 0.01);
}

TEST_CASE("upscale: in tiles the consistent reconstruction equals the untiled one, bit for bit") {
  // Noise flips everywhere, so tiles cut long triangles; regions of 16
  // rows make the canonical solve blocks and the tiles cut each other.
  const Image in = noise_image(40, 600, 2, 21);
  for (const char* name : {"box", "gauss:0.6", "bicubic"})
    for (auto [ow, oh] : {std::pair{80, 1200}, std::pair{100, 1500}, std::pair{120, 1800}}) {
      CAPTURE(name);
      CAPTURE(oh);
      UpscaleOptions options;
      options.model = parse_acquisition_model(name);
      options.region_rows = 16;
      options.tile_rows = -1;
      const Image whole = upscale(in, ow, oh, options);
      options.tile_rows = 150;
      UpscaleStats tiled;
      const Image tiles = upscale(in, ow, oh, options, &tiled);
      CHECK(tiled.tiles == 4);
      CHECK(max_difference(whole, tiles) == 0);
      // A band that ignores the reconstruction's reach differs near its cut.
      options.model.kind = AcquisitionModel::Kind::point;
      CHECK(max_difference(whole, upscale(in, ow, oh, options)) > 1e-3);
    }
}

TEST_CASE("upscale: a reduction on any axis is the plain interpolation under every model") {
  const Image in = smooth_test_image(20, 16, 3);
  UpscaleOptions point;
  point.model.kind = AcquisitionModel::Kind::point;
  for (auto [w, h] : {std::pair{10, 8}, std::pair{40, 12}, std::pair{15, 32}})
    for (const char* name : {"box", "bicubic", "gauss:0.5"}) {
      CAPTURE(w);
      CAPTURE(name);
      UpscaleOptions options;
      options.model = parse_acquisition_model(name);
      CHECK(max_difference(upscale(in, w, h, options), upscale(in, w, h, point)) == 0);
    }
}

TEST_CASE("make_consistent_streamed: the wavefront equals make_consistent on the whole output, bit for bit") {
  // Tall images, so that the wavefront's window moves many times: noise
  // (flips everywhere, long triangles) and flat regions (straight edges
  // drawn as steps, halos limited beside them); box at x2, x3, x4 with 0,
  // 1 and 2 mesh steps; then models and scales it does not stream, drawn
  // whole and corrected by make_consistent.
  Image noise = noise_image(40, 500, 2, 5);
  for (float& v : noise.pixels) v = 0.2f + 0.6f * v;
  const Image stripes = render_scene(find_scene("colour_regions"), 36, 420);
  struct Case {
    const Image* in;
    const char* model;
    int scale_num, scale_den, mesh_steps;
  };
  const Case cases[] = {{&noise, "box", 2, 1, 2},    {&noise, "box", 3, 1, 1},     {&noise, "box", 4, 1, 0},
                        {&stripes, "box", 2, 1, 2},  {&stripes, "box", 3, 1, 2},   {&stripes, "box", 4, 1, 1},
                        {&noise, "gauss:0.6", 2, 1, 2}, {&stripes, "box", 5, 2, 2}, {&stripes, "bicubic", 3, 1, 2}};
  for (const Case& k : cases) {
    const Image& in = *k.in;
    const int C = in.channels, ow = in.width * k.scale_num / k.scale_den, oh = in.height * k.scale_num / k.scale_den;
    CAPTURE(k.model);
    CAPTURE(oh);
    CAPTURE(k.mesh_steps);
    UpscaleOptions options;
    options.region_rows = 16;
    const Mesh2 mesh = upscale_mesh(in, options);
    RenderGrid grid;
    grid.width = ow, grid.height = oh;
    grid.scale_x = static_cast<double>(ow) / in.width, grid.scale_y = static_cast<double>(oh) / in.height;
    const std::vector<float> gradients = grid_gradients(in, options.slopes);

    ConsistencyOptions co;
    co.model = parse_acquisition_model(k.model);
    co.mesh_steps = k.mesh_steps;
    co.output_band_rows = 37;
    auto collect_into = [&](Image& whole, int& next_row, bool& in_order) {
      return [&whole, &next_row, &in_order, ow, C](Image rows, int first_row) {
        in_order = in_order && first_row == next_row && rows.width == ow && rows.channels == C;
        if (!in_order) return;
        std::copy(rows.pixels.begin(), rows.pixels.end(), whole.pixels.begin() + whole.index(0, first_row));
        next_row += rows.height;
      };
    };
    Image expected(ow, oh, C, -1.0f), streamed(ow, oh, C, -2.0f);
    int expected_rows = 0, streamed_rows = 0;
    bool expected_order = true, streamed_order = true;
    co.output_rows = collect_into(expected, expected_rows, expected_order);
    Image out = render_mesh(mesh, in.pixels, C, grid, nullptr, true, 0.0f, &gradients);
    ConsistencyStats whole_stats, stream_stats;
    make_consistent(out, mesh, in, co, &whole_stats);

    co.output_rows = collect_into(streamed, streamed_rows, streamed_order);
    int mesh_done = 0, rows_before_mesh_done = -1;
    co.mesh_done = [&] { ++mesh_done, rows_before_mesh_done = streamed_rows; };
    RenderStats surface_stats;
    // The gradients of the rows asked for, each row once, in order.
    const std::size_t row_gradients = static_cast<std::size_t>(in.width) * C * 2;
    int gradients_made = 0, most_asked = 0;
    bool gradients_in_order = true;
    const GradientRows gradient_rows = [&](int first, int end) {
      gradients_in_order = gradients_in_order && first == gradients_made && end > first && end <= in.height;
      gradients_made = end, most_asked = std::max(most_asked, end - first);
      return std::vector<float>(gradients.begin() + static_cast<std::ptrdiff_t>(row_gradients * first),
                                gradients.begin() + static_cast<std::ptrdiff_t>(row_gradients * end));
    };
    make_consistent_streamed(ow, oh, in.pixels, gradient_rows, mesh, in, co, &stream_stats, &surface_stats);
    CHECK(gradients_in_order);
    CHECK(gradients_made == in.height);
    CHECK(expected_order);
    CHECK(streamed_order);
    CHECK(expected_rows == oh);
    CHECK(streamed_rows == oh);
    CHECK(mesh_done == 1);
    CHECK(std::memcmp(expected.pixels.data(), streamed.pixels.data(), expected.pixels.size() * sizeof(float)) == 0);
    CHECK(stream_stats.mesh_steps == whole_stats.mesh_steps);
    CHECK(stream_stats.residual_before == whole_stats.residual_before);
    CHECK(stream_stats.residual_mesh == whole_stats.residual_mesh);
    CHECK(stream_stats.residual_after == whole_stats.residual_after);
    CHECK(stream_stats.step_edge_footprints == whole_stats.step_edge_footprints);
    CHECK(stream_stats.halo_footprints == whole_stats.halo_footprints);
    const bool streams = make_consistent_streams(co.model, in.width, in.height, ow, oh);
    CHECK(streams == (std::string(k.model) == "box" && k.scale_den == 1));
    CHECK(surface_stats.triangles == mesh.triangle_count());
    // Streamed, rows are handed out long before the whole output is made
    // (the mesh steps end at the last rows); else all of them after.
    if (streams) CHECK(rows_before_mesh_done > oh / 2);
    else CHECK(rows_before_mesh_done == 0);
    // Streamed, the gradients too are made a band of rows at a time.
    if (streams) CHECK(most_asked < in.height / 2);
    else CHECK(most_asked == in.height);
    if (std::string(k.model) == "box" && k.in == &stripes && k.scale_den == 1) CHECK(whole_stats.step_edge_footprints > 0);
  }
}

TEST_CASE("upscale: streamed, the default's rows equal the whole output's, bit for bit") {
  const Image in = test::sampled_image(50, 380, 3, [](double x, double y, int c) {
    return std::round((0.4 + 0.3 * std::sin(0.4 * x + 0.1 * c) * std::cos(0.23 * y) + (x > 0.3 * y ? 0.2 : 0)) * 255) /
           255;
  });
  for (int scale : {2, 4}) {
    CAPTURE(scale);
    UpscaleOptions options;
    options.region_rows = 32;
    const Image whole = upscale(in, in.width * scale, in.height * scale, options);
    Image rows(in.width * scale, in.height * scale, 3, -1.0f);
    int next = 0;
    options.output_rows = [&](Image part, int first_row) {
      CHECK(first_row == next);
      std::copy(part.pixels.begin(), part.pixels.end(), rows.pixels.begin() + rows.index(0, first_row));
      next += part.height;
    };
    upscale(in, in.width * scale, in.height * scale, options);
    CHECK(next == rows.height);
    CHECK(std::memcmp(whole.pixels.data(), rows.pixels.data(), whole.pixels.size() * sizeof(float)) == 0);
  }
}
