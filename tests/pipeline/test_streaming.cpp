// The streaming pipeline: the rows upscale() hands to
// UpscaleOptions::output_rows are the image it returns otherwise, bit for
// bit, each row once, top to bottom.

#include "eval/synthetic_scenes.hpp"
#include "pipeline/upscale.hpp"

#include <doctest/doctest.h>

#include <random>

using namespace ddt;

namespace {

Image textured(int w, int h) {
  const Image a = render_scene(find_scene("colour_regions"), w, h);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> noise(-0.03f, 0.03f);
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = a.at(x, y, c) + noise(rng);
  return img;
}

// The image upscale() streams, gathered; checks the bands' order on the way.
Image streamed(const Image& in, int ow, int oh, UpscaleOptions opt, int& bands) {
  Image gathered(ow, oh, in.channels, -1.0f);
  int next = 0;
  bands = 0;
  opt.output_rows = [&](Image rows, int first) {
    CHECK(first == next);
    CHECK(rows.width == ow);
    REQUIRE(first + rows.height <= oh);
    std::copy(rows.pixels.begin(), rows.pixels.end(),
              gathered.pixels.begin() + static_cast<std::ptrdiff_t>(gathered.index(0, first)));
    next = first + rows.height;
    ++bands;
  };
  const Image returned = upscale(in, ow, oh, opt);
  CHECK(returned.empty());
  CHECK(next == oh);
  return gathered;
}

}  // namespace

TEST_CASE("upscale: streamed rows equal the whole output, whole and in tiles, point and box models") {
  const Image in = textured(120, 100);
  for (const char* model : {"point", "box"})
  for (const char* render : {"linear", "cubic"})
    for (int tile_rows : {-1, 29}) {
      CAPTURE(model);
      CAPTURE(render);
      CAPTURE(tile_rows);
      UpscaleOptions opt;
      opt.model = parse_acquisition_model(model);
      opt.render = render_by_name(render);
      opt.region_rows = 8;
      opt.tile_rows = tile_rows;
      opt.output_band_rows = 17;  // bands that divide neither the output nor the tiles
      const Image whole = upscale(in, 300, 250, opt);
      int bands = 0;
      const Image rows = streamed(in, 300, 250, opt, bands);
      CHECK(bands >= 250 / 17);
      CHECK(rows.pixels == whole.pixels);
    }
}

TEST_CASE("upscale: streamed rows equal the whole output under the consistent reconstruction") {
  const Image in = textured(48, 40);
  struct Case {
    const char* model;
    int out_w, out_h, bands;
  };
  // Box at integer scales hands out a band as soon as its footprints are
  // finished (8 input rows of 25 / 3 output rows each: 5 bands); other
  // models and scales finish the whole output first, then hand it out in
  // bands of 25 rows.
  for (const Case& c : {Case{"box", 144, 120, 5}, Case{"box", 150, 125, 5}, Case{"gauss:0.5", 144, 120, 5},
                        Case{"bicubic", 96, 80, 4}}) {
    CAPTURE(c.model);
    CAPTURE(c.out_w);
    UpscaleOptions opt;
    opt.model = parse_acquisition_model(c.model);
    opt.output_band_rows = 25;
    const Image whole = upscale(in, c.out_w, c.out_h, opt);
    int bands = 0;
    const Image rows = streamed(in, c.out_w, c.out_h, opt, bands);
    CHECK(bands == c.bands);
    CHECK(rows.pixels == whole.pixels);
  }
}

TEST_CASE("upscale: streamed bands of the consistent reconstruction hold its straight edges and halo limits") {
  // Flat regions with straight borders: footprints drawn as edges and
  // halos limited in every band of the box model at x4.
  const Image in = render_scene(find_scene("colour_regions"), 48, 40);
  UpscaleOptions opt;
  opt.output_band_rows = 13;
  const Image whole = upscale(in, 192, 160, opt);
  int bands = 0;
  const Image rows = streamed(in, 192, 160, opt, bands);
  CHECK(bands == 13);  // 160 rows in bands of at most 13
  CHECK(rows.pixels == whole.pixels);
  UpscaleOptions without = opt;
  without.step_edges = false;
  CHECK(upscale(in, 192, 160, without).pixels != whole.pixels);
}
