// Tiles (bands of input rows with overlapping margins) and row windows of
// the rasterizer: a tiled run must equal the untiled run bit for bit.

#include "util/error.hpp"
#include "image/image_mesh.hpp"
#include "image/rasterizer.hpp"
#include "eval/synthetic_scenes.hpp"
#include "test_support.hpp"
#include "image/triangulation.hpp"
#include "pipeline/banded_upscale.hpp"
#include "pipeline/upscale.hpp"
#include "consistency/consistent_reconstruction.hpp"
#include "consistency/input_statistics.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdio>
#include <random>

using namespace ddt;

namespace {

// A medium image with edges, smooth parts and fine texture (many flips).
Image textured(int w, int h) {
  const Image a = render_scene(find_scene("colour_regions"), w, h);
  const Image b = render_scene(find_scene("strokes"), w, h);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> noise(-0.03f, 0.03f);
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = 0.6f * a.at(x, y, c) + 0.4f * b.at(x, y, 0) + noise(rng);
  return img;
}

long long differing(const Image& a, const Image& b) {
  long long n = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) n += a.pixels[i] != b.pixels[i];
  return n;
}

}  // namespace

TEST_CASE("upscale: a tiled run equals the untiled run bit for bit") {
  const Image in = textured(150, 130);
  for (const Render render : {Render::linear, Render::cubic})
    for (const char* cost : {"sederberg", "variance"})
      for (double scale : {3.0, 2.5}) {
        CAPTURE(to_string(render));
        CAPTURE(cost);
        CAPTURE(scale);
        UpscaleOptions opt;
  opt.model.kind = AcquisitionModel::Kind::point;
        opt.model.kind = AcquisitionModel::Kind::point;  // the consistent reconstruction does not tile yet
        opt.render = render;
        opt.cost = cost;
        opt.region_rows = 8;  // many regions, so that bands cut through them
        const int ow = static_cast<int>(150 * scale), oh = static_cast<int>(130 * scale);
        UpscaleStats whole, bands;
        const Image a = upscale(in, ow, oh, opt, &whole);
        opt.tile_rows = 37;  // not a multiple of the regions: bands cut regions anywhere
        const Image b = upscale(in, ow, oh, opt, &bands);
        CHECK(whole.tiles == 1);
        CHECK(bands.tiles == 4);
        CHECK(whole.regions > 4);
        CHECK(whole.flips > 1000);
        REQUIRE(a.pixels.size() == b.pixels.size());
        CHECK(differing(a, b) == 0);
      }
}

TEST_CASE("upscale: automatic tiling under a small memory budget gives the same image") {
  const Image in = textured(60, 700);
  UpscaleOptions opt;
  opt.model.kind = AcquisitionModel::Kind::point;
  opt.region_rows = 16;  // the same schedule in both runs (automatic only turns regions on for large images)
  UpscaleStats whole, bands;
  const Image a = upscale(in, 120, 1400, opt, &whole);
  opt.max_memory = 1;  // nothing fits: bands of the smallest height, 256 rows
  const Image b = upscale(in, 120, 1400, opt, &bands);
  CHECK(whole.tiles == 1);
  CHECK(bands.tiles == 3);
  CHECK(differing(a, b) == 0);
  opt.tile_rows = -1;  // never
  UpscaleStats never;
  upscale(in, 120, 1400, opt, &never);
  CHECK(never.tiles == 1);
}

TEST_CASE("render_mesh: a window of rows is the same rows of the whole image") {
  const Image in = textured(40, 30);
  Mesh2 mesh = delaunay_triangulation(test::grid_points(40, 30));
  RenderGrid g;
  g.width = 97, g.height = 71;  // scale 2.425 x 2.3667: the general (filtered) path
  g.scale_x = 97.0 / 40, g.scale_y = 71.0 / 30;
  for (double s : {1.0, 4.0}) {
    if (s == 4.0) g.width = 160, g.height = 120, g.scale_x = g.scale_y = 4.0;  // the exact path
    const Image whole = render_mesh(mesh, in.pixels, 3, g);
    RenderGrid part = g;
    part.first_row = 13, part.rows = 29;
    RenderStats st;
    const Image window = render_mesh(mesh, in.pixels, 3, part, &st);
    REQUIRE(window.height == 29);
    CHECK(st.uncovered == 0);
    long long diff = 0;
    for (int y = 0; y < 29; ++y)
      for (int x = 0; x < g.width; ++x)
        for (int c = 0; c < 3; ++c) diff += window.at(x, y, c) != whole.at(x, y + 13, c);
    CHECK(diff == 0);
    // Into a larger image: only the rows asked for change.
    Image into(g.width, 50, 3, -1.0f);
    render_mesh_into(into, 5, mesh, in.pixels, 3, part);
    for (int x = 0; x < g.width; ++x) {
      CHECK(into.at(x, 4, 0) == -1.0f);
      CHECK(into.at(x, 34, 0) == -1.0f);
      CHECK(into.at(x, 5, 1) == whole.at(x, 13, 1));
      CHECK(into.at(x, 33, 2) == whole.at(x, 41, 2));
    }
    Image small(g.width, 10, 3);
    CHECK_THROWS(render_mesh_into(small, 0, mesh, in.pixels, 3, part));
  }
}

TEST_CASE("upscale_rows: bands with margins are the whole image's rows, bit for bit") {
  const int H = 720;  // tall enough for cuts with the reconstruction's margins
  const Image in = textured(90, H);
  const InputStatistics statistics = input_statistics(in);
  for (const char* model : {"point", "box", "bicubic"})
  for (double scale : {2.0, 2.5}) {
    CAPTURE(model);
    CAPTURE(scale);
    UpscaleOptions opt;
    opt.model = parse_acquisition_model(model);
    opt.region_rows = 8;
    const int ow = static_cast<int>(90 * scale), oh = static_cast<int>(H * scale);
    UpscaleStats whole;
    const Image a = upscale(in, ow, oh, opt, &whole);
    // Triangles of up to two regions' height (a guess; a band with too
    // narrow a margin would throw).
    const int margin = band_margin_needed(whole.iterations + 2, 8) +
                       consistency_margin_needed(16, opt.model, 90, H, ow, oh);
    if (opt.model.kind != AcquisitionModel::Kind::point) {  // too narrow for the reconstruction
      Image rows(90, 80, 3);
      std::copy(in.pixels.begin(), in.pixels.begin() + static_cast<std::ptrdiff_t>(rows.pixels.size()),
                rows.pixels.begin());
      CHECK_THROWS_WITH_AS(upscale_rows(rows, 0, H, 0, 40, ow, oh, opt, nullptr, &statistics),
                           doctest::Contains("consistent reconstruction"), Error);
    }
    // Bands of 35 rows (regions cut anywhere), each from its rows and margins only.
    int cut = 0;
    for (int first = 0; first < H; first += 35) {
      const int end = std::min(H, first + 35);
      const int top = std::max(0, first - margin), bottom = std::min(H, end + margin);
      cut += top > 0 && bottom < H;
      Image rows(90, bottom - top, 3);
      std::copy(in.pixels.begin() + static_cast<std::ptrdiff_t>(in.index(0, top)),
                in.pixels.begin() + static_cast<std::ptrdiff_t>(in.index(0, bottom - 1) + 90 * 3), rows.pixels.begin());
      const Image band = upscale_rows(rows, top, H, first, end, ow, oh, opt, nullptr, &statistics);
      const int y0 = output_row_of(first, H, oh);
      REQUIRE(band.height == output_row_of(end, H, oh) - y0);
      long long differ = 0;
      for (std::size_t i = 0; i < band.pixels.size(); ++i)
        differ += band.pixels[i] != a.pixels[static_cast<std::size_t>(y0) * ow * 3 + i];
      CHECK(differ == 0);
    }
    CHECK(cut >= 2);  // bands cut on both sides
  }
}

TEST_CASE("upscale_rows: refuses what a band cannot reproduce") {
  const Image in = textured(40, 60);
  Image rows(40, 30, 3);
  std::copy(in.pixels.begin(), in.pixels.begin() + static_cast<std::ptrdiff_t>(rows.pixels.size()), rows.pixels.begin());
  UpscaleOptions opt;  // the box model: a band needs the whole input's statistics
  CHECK_THROWS_WITH_AS(upscale_rows(rows, 0, 60, 0, 20, 80, 120, opt), doctest::Contains("statistics"), Error);
  opt.model.kind = AcquisitionModel::Kind::point;
  opt.region_rows = 4;
  CHECK_THROWS_WITH_AS(upscale_rows(rows, 0, 60, 0, 30, 80, 120, opt), doctest::Contains("too narrow"), Error);
  CHECK_THROWS_AS(upscale_rows(rows, 0, 60, 10, 40, 80, 120, opt), Error);  // rows not held
  // The whole image as one band is upscale() itself, in any model.
  const Image whole = upscale(in, 80, 120, UpscaleOptions{});
  const Image band = upscale_rows(in, 0, 60, 0, 60, 80, 120, UpscaleOptions{});
  CHECK(differing(whole, band) == 0);
}

TEST_CASE("upscale_banded: an image read and enlarged by bands is upscale()'s, reading each row twice") {
  const int W = 60, H = 700;
  const Image in = textured(W, H);
  for (const char* model : {"box", "point"}) {
    CAPTURE(model);
    UpscaleOptions opt;
    opt.model = parse_acquisition_model(model);
    opt.region_rows = 8;
    const Image whole = upscale(in, 2 * W, 2 * H, opt);
    std::vector<int> reads(H, 0);
    int last_end = 0, backwards = 0;
    const RowSource source{W, H, 3, [&](int first, int end, float* rows) {
                             backwards += first < last_end && first != 0;
                             last_end = end;
                             for (int y = first; y < end; ++y) ++reads[y];
                             std::copy(in.pixels.begin() + static_cast<std::ptrdiff_t>(in.index(0, first)),
                                       in.pixels.begin() + static_cast<std::ptrdiff_t>(in.index(0, end - 1) + W * 3),
                                       rows);
                           }};
    Image gathered(2 * W, 2 * H, 3, -1.0f);
    int next = 0;
    opt.output_rows = [&](Image rows, int first_row) {
      CHECK(first_row == next);
      std::copy(rows.pixels.begin(), rows.pixels.end(),
                gathered.pixels.begin() + static_cast<std::ptrdiff_t>(gathered.index(0, first_row)));
      next = first_row + rows.height;
    };
    int reruns = 0;  // bands redone with a wider margin re-read the rows above
    opt.log = [&](const std::string& line) { reruns += line.find("again") != std::string::npos; };
    const UpscaleStats stats = upscale_banded(source, 2 * W, 2 * H, opt, 100);
    CHECK(stats.tiles == 7);
    CHECK(next == 2 * H);
    CHECK(gathered.pixels == whole.pixels);
    CHECK(backwards <= reruns);  // top to bottom, each pass
    // The consistent model reads the input once for its statistics, then by bands.
    const int passes = opt.model.kind == AcquisitionModel::Kind::point ? 1 : 2;
    CHECK(*std::min_element(reads.begin(), reads.end()) == passes);
    CHECK(*std::max_element(reads.begin(), reads.end()) <= passes + reruns);
    MESSAGE(model << ": " << reruns << " bands redone with a wider margin");
  }
  // A source that fails stops the job with its error.
  UpscaleOptions opt;
  opt.region_rows = 8;
  opt.output_rows = [](Image, int) {};
  const RowSource broken{W, H, 3, [](int, int, float*) { throw Error("cannot read 'x.png': damaged"); }};
  CHECK_THROWS_WITH_AS(upscale_banded(broken, 2 * W, 2 * H, opt, 100), "cannot read 'x.png': damaged", Error);
  opt.optimizer = Optimizer::anneal;
  CHECK_THROWS_WITH_AS(upscale_banded(broken, 2 * W, 2 * H, opt, 100), doctest::Contains("region schedule"), Error);
}

TEST_CASE("banded_rows: the most rows whose band fits the budget, margins included") {
  const UpscaleOptions opt;  // the box model: margins of a few hundred rows
  const int W = 8192, H = 30000, C = 3;
  const int margin = planned_band_margin(optimizer_region_rows(W, H, opt), true, opt.model, W, H, 2 * W, 2 * H);
  CHECK(margin > 100);
  double last = 0;
  for (double gigabytes : {2.0, 4.0, 12.0}) {
    CAPTURE(gigabytes);
    const double budget = gigabytes * 1e9;
    const int rows = banded_rows(W, H, C, 2 * W, 2 * H, opt, budget);
    CHECK(rows > last);
    CHECK(banded_bytes(W, H, C, 2 * W, 2 * H, rows, margin) <= budget);
    CHECK(banded_bytes(W, H, C, 2 * W, 2 * H, rows + 2, margin) > budget);
    last = rows;
  }
  // More output per input pixel, fewer rows; a budget below a band's margins, the smallest band.
  CHECK(banded_rows(W, H, C, 4 * W, 4 * H, opt, 4e9) < banded_rows(W, H, C, 2 * W, 2 * H, opt, 4e9));
  CHECK(banded_rows(W, H, C, 2 * W, 2 * H, opt, 1) == 256);
  CHECK(banded_rows(W, 300, C, 2 * W, 600, opt, 1e12) == 300);
}

TEST_CASE("upscale: the streamed consistent reconstruction from meshes made by bands is the one mesh's, bit for bit") {
  const int W = 60, H = 400;
  const Image in = textured(W, H);
  for (const Render render : {Render::cubic, Render::linear})
    for (int scale : {2, 3}) {
      CAPTURE(to_string(render));
      CAPTURE(scale);
      UpscaleOptions opt;  // the box model: the wavefront
      opt.render = render;
      opt.region_rows = 8;  // many regions, so that the bands' margins matter
      // The input held whole (upscale), or read by rows from a source
      // (upscale_by_rows: a window of rows, after a pass for its statistics).
      auto streamed = [&](int mesh_band_rows, std::vector<std::string>* lines, bool by_rows = false) {
        Image gathered(scale * W, scale * H, 3, -1.0f);
        int next = 0;
        UpscaleOptions o = opt;
        o.mesh_band_rows = mesh_band_rows;
        o.output_rows = [&](Image rows, int first_row) {
          CHECK(first_row == next);
          std::copy(rows.pixels.begin(), rows.pixels.end(),
                    gathered.pixels.begin() + static_cast<std::ptrdiff_t>(gathered.index(0, first_row)));
          next = first_row + rows.height;
        };
        if (lines) o.log = [lines](const std::string& line) { lines->push_back(line); };
        if (by_rows) {
          REQUIRE(upscale_reads_by_rows(W, H, 3, scale * W, scale * H, o));
          const RowSource source{W, H, 3, [&](int first, int end, float* rows) {
                                   std::copy(in.pixels.begin() + static_cast<std::ptrdiff_t>(in.index(0, first)),
                                             in.pixels.begin() + static_cast<std::ptrdiff_t>(in.index(0, end)), rows);
                                 }};
          upscale_by_rows(source, scale * W, scale * H, o);
        } else {
          upscale(in, scale * W, scale * H, o);
        }
        CHECK(next == scale * H);
        return gathered;
      };
      const Image one = streamed(-1, nullptr);
      std::vector<std::string> lines;
      const Image banded = streamed(45, &lines);  // not a multiple of the regions
      CHECK(differing(one, banded) == 0);
      // Nine bands; a band whose optimizer ran more phases than its margin
      // holds is made again with a wider one, and drawn from that.
      const auto summary = std::find_if(lines.begin(), lines.end(),
                                        [](const std::string& line) { return line.rfind("mesh bands: ", 0) == 0; });
      REQUIRE(summary != lines.end());
      CHECK(summary->rfind("mesh bands: 9 of 45 rows", 0) == 0);
      // Each band takes over the rows the one before still drew, which is freed first.
      CHECK(summary->find("at most 1 held at once") != std::string::npos);
      MESSAGE(*summary);
      // Read by rows: the same bits, from fewer rows of the input than its height.
      lines.clear();
      const Image by_rows = streamed(45, &lines, true);
      CHECK(differing(one, by_rows) == 0);
      const auto held = std::find_if(lines.begin(), lines.end(),
                                     [](const std::string& line) { return line.rfind("input: read by rows", 0) == 0; });
      REQUIRE(held != lines.end());
      MESSAGE(*held);
      int most = 0;
      REQUIRE(std::sscanf(held->c_str(), "input: read by rows, at most %d", &most) == 1);
      CHECK(most < H);
      CHECK(held->find(", 0 read again") != std::string::npos);  // released only behind every step
      // One mesh does not read by rows.
      UpscaleOptions one_mesh = opt;
      one_mesh.mesh_band_rows = -1;
      CHECK_FALSE(upscale_reads_by_rows(W, H, 3, scale * W, scale * H, one_mesh));
    }
}
