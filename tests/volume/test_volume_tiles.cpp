#include "eval/sequence_scenes.hpp"
#include "eval/volume_fields.hpp"
#include "util/error.hpp"
#include "volume/sequence_upscale.hpp"
#include "volume/volume_tiles.hpp"

#include <doctest/doctest.h>

using namespace ddt;

namespace {

// upscale_in_tiles on a volume held whole; the slices written in order, each once.
Volume tiled(const Volume& src, const std::array<int, 4>& out, const VolumeUpscaleOptions& options,
             const VolumeTiling& tiling, VolumeTilingStats* stats = nullptr) {
  Volume result(out, src.channels, 0.0f);
  const int axis = src.nt > 1 ? 3 : 2;
  const std::size_t in_slice = src.voxels.size() / src.size()[axis];
  const std::size_t out_slice = result.voxels.size() / out[axis];
  int next = 0;
  upscale_in_tiles(
      src.size(), out, src.channels, options, tiling,
      [&](int k, float* samples) { std::copy_n(src.voxels.begin() + std::ptrdiff_t(k * in_slice), in_slice, samples); },
      [&](const float* samples, int g) {
        REQUIRE(g == next++);
        std::copy_n(samples, out_slice, result.voxels.begin() + std::ptrdiff_t(g * out_slice));
      },
      stats);
  CHECK(next == out[axis]);
  return result;
}

}  // namespace

TEST_CASE("upscale_in_tiles: exact tiles of a 3D volume along z are the untiled result bit for bit") {
  const Volume v = sample_field(find_volume_field("hydrogen"), 14, 14, 28, 2);
  for (const bool node_z : {false, true}) {
    VolumeUpscaleOptions o;
    o.region_slices = 4;  // several slabs, so that the cuts matter
    o.node_centred[2] = node_z;
    const std::array<int, 4> out{28, 28, node_z ? 27 * 2 + 1 : 56, 1};
    const Volume whole = upscale_volume(v, out, o);
    VolumeTiling tiling;
    tiling.tile_slices = 4;
    tiling.margin_slices = 0;  // the least: widened as the phases need
    VolumeTilingStats stats;
    const Volume tiles = tiled(v, out, o, tiling, &stats);
    MESSAGE("z " << (node_z ? "node" : "cell") << "-centred: " << stats.tiles << " tiles, margin " << stats.margin_slices
                 << ", " << stats.reruns << " run again");
    CHECK(stats.tiles > 2);
    CHECK(stats.region_slices == 4);
    CHECK(stats.margin_slices % 4 == 0);
    CHECK(tiles.voxels == whole.voxels);
    // Loose tiles with a narrow margin are not exact (so the test above can fail).
    tiling.exact = false;
    tiling.margin_slices = 1;
    CHECK(tiled(v, out, o, tiling).voxels != whole.voxels);
  }
}

TEST_CASE("upscale_in_tiles: exact tiles of a series along time, and of image sequences, are the untiled result") {
  SUBCASE("4D series, time x2, space x1.5 (tiles need a whole scale along time only)") {
    const Volume v = sample_series_field(find_volume_series_field("moving-sphere"), {8, 8, 8, 13}, 2);
    VolumeUpscaleOptions o;
    o.region_slices = 3;
    o.node_centred[3] = true;
    o.presmooth = presmooth_in_space(true);
    const std::array<int, 4> out{12, 12, 12, 25};
    const Volume whole = upscale_volume(v, out, o);
    VolumeTiling tiling;
    tiling.tile_slices = 3;
    VolumeTilingStats stats;
    CHECK(tiled(v, out, o, tiling, &stats).voxels == whole.voxels);
    CHECK(stats.tiles >= 2);
  }
  // The bar turns (the lattice's mesh); the strokes move (-3, 2) px a
  // frame (a mesh sheared along that motion), 13 frames before they leave;
  // "strokes, given": a shear given as (0.3, -0.7), which is not exact in
  // doubles at every frame (taken to 1/8 pixel, it is).
  // "strokes, zoom given": the same with a zoom of 3 % a frame.
  for (const std::string name : {"bar", "strokes", "strokes, given", "strokes, zoom given"}) {
    CAPTURE(name);
    const std::string scene = name.substr(0, name.find(','));
    const bool given = name != scene;
    const int frames = scene == "bar" ? 25 : 13, size = scene == "bar" ? 32 : 48;
    std::vector<Image> in;
    for (int k = 0; k < frames; ++k) in.push_back(render_sequence_frame(scene, 4 * k, size, size));
    auto run = [&](const SequenceUpscaleOptions& o, SequenceUpscaleStats* stats) {
      std::vector<Image> out;
      upscale_sequence(frames, size, size, 1, [&](int k) { return in.at(std::size_t(k)); }, size, size, 3, o,
                       [&](Image f, int) { out.push_back(std::move(f)); }, stats);
      return out;
    };
    SequenceUpscaleOptions o;
    o.volume.region_slices = 4;
    o.volume.render = Render::cubic;
    if (given) set_motion(o, name == "strokes, given" ? "0.3,-0.7" : "0.3,-0.7,1.03");
    o.tile_frames = 1000;
    const std::vector<Image> whole = run(o, nullptr);
    o.tile_frames = 4;
    o.exact_tiles = true;
    SequenceUpscaleStats stats;
    const std::vector<Image> tiles = run(o, &stats);
    REQUIRE(tiles.size() == whole.size());
    int differing = 0;
    for (std::size_t g = 0; g < whole.size(); ++g) differing += tiles[g].pixels != whole[g].pixels;
    CHECK(differing == 0);
    CHECK(stats.tiles >= 2);
    CHECK(stats.motion.found == (name == "strokes"));
  }
}

TEST_CASE("upscale_in_tiles: the margin needed grows with the phases - bad scales are refused with one line") {
  CHECK(tile_margin_needed(1, 16) == 18);
  CHECK(tile_margin_needed(3, 16) == 34);
  CHECK(tile_margin_needed(3, 5) == 14);  // half a slab rounds up
  CHECK(tiled_output_slices(5, 3, true) == 13);
  CHECK(tiled_output_slices(5, 3, false) == 15);
  const Volume v = sample_field(find_volume_field("sphere"), 6, 6, 6, 1);
  VolumeTiling tiling;
  tiling.tile_slices = 2;
  CHECK_THROWS_WITH_AS(tiled(v, {9, 9, 9, 1}, {}, tiling), doctest::Contains("whole scale along z"), Error);
  tiling.margin_slices = -1;
  CHECK_THROWS_AS(tiled(v, {12, 12, 12, 1}, {}, tiling), Error);
  // A thin axis makes it the 2D method's problem: enlarged whole, one tile.
  Volume thin({1, 6, 10, 1}, 1, 0.0f);
  for (std::size_t i = 0; i < thin.voxels.size(); ++i) thin.voxels[i] = float(i % 7) / 7;
  tiling.margin_slices = 1;
  VolumeTilingStats stats;
  CHECK(tiled(thin, {2, 12, 20, 1}, {}, tiling, &stats).voxels == upscale_volume(thin, {2, 12, 20, 1}).voxels);
  CHECK(stats.tiles == 1);
  tiling.axis_scale = 2.5;
  CHECK_THROWS_WITH_AS(tiled(thin, {2, 12, 25, 1}, {}, tiling), doctest::Contains("fractional scale"), Error);
}
