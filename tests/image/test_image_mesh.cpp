#include "util/error.hpp"
#include "image/image_mesh.hpp"
#include "eval/synthetic_scenes.hpp"
#include "pipeline/upscale.hpp"

#include <doctest/doctest.h>

using namespace ddt;

TEST_CASE("image_mesh: the optimizer chosen changes the mesh, and a bad one is an error") {
  const Image src = render_scene(find_scene("strokes"), 40, 36);
  UpscaleOptions lawson, anneal;
  anneal.optimizer = Optimizer::anneal;
  const Mesh2 a = image_mesh(src, lawson), b = image_mesh(src, anneal);
  CHECK(a.tri != b.tri);
  UpscaleOptions bad;
  bad.optimizer = Optimizer::anneal;
  bad.anneal.cooling = 1.0;
  CHECK_THROWS_AS(image_mesh(src, bad), Error);
}

TEST_CASE("drive_channels: alpha never drives, luma is one channel, too many channels is an error") {
  Image rgba(4, 4, 4, 0.25f);
  UpscaleOptions options;
  options.alpha_channel = 3;
  DriveChannels d = drive_channels(rgba, options);
  CHECK(d.K == 3);
  CHECK(d.colour == std::vector<int>{0, 1, 2});
  CHECK_FALSE(d.identity);
  rgba.at(1, 2, 0) = 1.0f;
  rgba.at(1, 2, 1) = 0.5f;
  rgba.at(1, 2, 2) = 0.0f;
  options.luma_cost = true;
  d = drive_channels(rgba, options);
  REQUIRE(d.K == 1);
  const std::vector<float> luma = drive_values(rgba.pixels.data(), rgba.pixel_count(), 4, d);
  CHECK(luma[2 * 4 + 1] == doctest::Approx(0.299 + 0.587 * 0.5));
  CHECK(luma[0] == doctest::Approx(0.25));
  const Image many(4, 4, max_cost_channels + 1);
  CHECK_THROWS_AS(drive_channels(many, UpscaleOptions{}), Error);
  UpscaleOptions luma_only;
  luma_only.luma_cost = true;
  CHECK(drive_channels(many, luma_only).K == 1);
}

TEST_CASE("optimizer_region_rows: automatic regions only on large images, or as asked") {
  UpscaleOptions options;
  CHECK(optimizer_region_rows(64, 64, options) == 0);
  CHECK(optimizer_region_rows(2048, 2048, options) > 0);
  options.region_rows = 5;
  CHECK(optimizer_region_rows(64, 64, options) == 5);
  options.region_rows = -1;
  CHECK(optimizer_region_rows(2048, 2048, options) == 0);
  options.region_rows = 5;
  CHECK(optimizer_region_rows(1, 64, options) == 0);
}
