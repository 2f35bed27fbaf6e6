#include "volume/volume_tiles.hpp"

#include "util/error.hpp"
#include "util/timing.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

namespace ddt {
namespace {

int round_up(int value, int multiple) { return (value + multiple - 1) / multiple * multiple; }

// The sizes the mesh reconstruction sees (volume_upscale.cpp): axes of one
// sample dropped while three remain, x, y, z, t order kept.
std::array<int, 4> mesh_problem_size(const std::array<int, 4>& in) {
  std::array<bool, 4> keep{};
  int kept = 0;
  for (int a = 0; a < 4; ++a) kept += keep[a] = in[a] > 1;
  for (int a = 0; a < 4 && kept < 3; ++a)
    if (!keep[a]) keep[a] = true, ++kept;
  std::array<int, 4> size{1, 1, 1, 1};
  for (int a = 0, j = 0; a < 4; ++a)
    if (keep[a]) size[j++] = in[a];
  return size;
}

}  // namespace

int tiled_output_slices(int slices, int scale, bool node_centred) {
  return node_centred ? (slices - 1) * scale + 1 : slices * scale;
}

int default_tile_slices(long long samples_per_slice, int margin_slices) {
  const long long slices = std::max(1LL, (1LL << 22) / std::max(1LL, samples_per_slice));
  return static_cast<int>(std::max(1LL, slices - 2LL * std::max(0, margin_slices)));
}

int tile_margin_needed(int phases, int region_slices) { return (phases + 1) * ((region_slices + 1) / 2) + 2; }

void upscale_in_tiles(const std::array<int, 4>& in, const std::array<int, 4>& out, int channels,
                      const VolumeUpscaleOptions& options, const VolumeTiling& tiling,
                      const std::function<void(int, float*)>& read, const std::function<void(const float*, int)>& write,
                      VolumeTilingStats* stats) {
  for (int a = 0; a < 4; ++a)
    if (in[a] < 1 || out[a] < 1) throw Error("the input and the output must have at least one sample on every axis");
  if (channels < 1) throw Error("the volume has no channels");
  if (tiling.margin_slices < 0) throw Error("the tile margin must be at least 0 slices");
  const int axis = in[3] > 1 ? 3 : 2;
  const bool node = options.node_centred[axis] && in[axis] > 1;
  const int n = in[axis];
  // Units tiled: the n - 1 intervals between node-centred slices, or the n cells.
  const int units = node ? n - 1 : n;
  const double exact_scale = node ? double(out[axis] - 1) / std::max(1, n - 1) : double(out[axis]) / n;
  if (n > 1 && (exact_scale < 1 || exact_scale != std::floor(exact_scale)))
    throw Error(std::string("tiles need a whole scale along ") + (axis == 3 ? "time" : "z") + " (" +
                (node ? "(n - 1) * S + 1" : "n * S") + " output slices)");
  if (n == 1) {  // nothing to tile: the one slice, enlarged (and repeated) whole
    Volume whole(in, channels, 0.0f);
    read(0, whole.voxels.data());
    const Volume result = upscale_volume(whole, out, options);
    const std::size_t out_slice = result.voxels.size() / out[axis];
    for (int g = 0; g < out[axis]; ++g) write(result.voxels.data() + g * out_slice, g);
    if (stats) *stats = VolumeTilingStats{}, stats->tiles = 1;
    return;
  }
  const int scale = static_cast<int>(exact_scale);

  std::size_t in_slice = static_cast<std::size_t>(channels), out_slice = static_cast<std::size_t>(channels);
  for (int a = 0; a < axis; ++a) in_slice *= in[a], out_slice *= out[a];
  const std::array<int, 4> problem = mesh_problem_size(in);
  const bool slabbed = tiling.exact && problem[2] > 1;  // a 3D (or 4D) mesh problem: the slab schedule runs
  int tile = tiling.tile_slices > 0 ? tiling.tile_slices
                                    : default_tile_slices(static_cast<long long>(in_slice / channels), tiling.margin_slices);
  int margin = tiling.margin_slices;
  VolumeUpscaleOptions o = options;
  int region = 0;
  if (slabbed) {
    region = options.region_slices > 0 ? options.region_slices : volume_region_slices(problem);
    if (region >= n) tile = n;  // one slab: the untiled run is sequential, so one tile (a small mesh anyway)
    tile = round_up(tile, region);
    margin = round_up(std::max(margin, tile_margin_needed(3, region)), region);  // 3 phases: common; more widen it
    o.region_slices = region;
  }
  // Smoothing along the tiled axis reads 3 sigma across a cut.
  const int smoothing_reach = static_cast<int>(std::ceil(3 * options.presmooth[axis]));
  if (tiling.progress) tiling.progress->begin("enlarge", out[axis]);

  VolumeTilingStats local;
  local.region_slices = region;
  std::deque<std::vector<float>> cache;  // input slices cache_first, cache_first + 1, ...
  int cache_first = 0;
  for (int a0 = 0;;) {
    // The tile's own units are [a0, a1); lo..hi adds the margins; its input
    // slices are lo..hi (node-centred) or lo..hi - 1.
    const int a1 = std::min(a0 + tile, units);
    const int lo = std::max(0, a0 - margin), hi = std::min(units, a1 + margin);
    const int first_slice = lo, slices = node ? hi - lo + 1 : hi - lo;
    while (!cache.empty() && cache_first < first_slice) cache.pop_front(), ++cache_first;
    if (cache.empty()) cache_first = first_slice;
    auto t0 = Clock::now();
    while (cache_first + static_cast<int>(cache.size()) < first_slice + slices) {
      cache.emplace_back(in_slice);
      read(cache_first + static_cast<int>(cache.size()) - 1, cache.back().data());
    }
    local.seconds_read += seconds_since(t0);

    std::array<int, 4> part_size = in, part_out = out;
    part_size[axis] = slices;
    part_out[axis] = tiled_output_slices(slices, scale, node);
    Volume part(part_size, channels, 0.0f);
    for (int k = 0; k < slices; ++k) {
      const std::vector<float>& slice = cache[static_cast<std::size_t>(first_slice - cache_first + k)];
      std::copy(slice.begin(), slice.end(), part.voxels.begin() + static_cast<std::ptrdiff_t>(k * in_slice));
    }
    VolumeUpscaleStats vs;
    const Volume result = upscale_volume(part, part_out, o, &vs);
    local.flips += vs.flips.total() + vs.planar_flips + vs.presmooth_flips;
    local.seconds_triangulate += vs.seconds_triangulate;
    local.seconds_optimize += vs.seconds_optimize;
    local.seconds_render += vs.seconds_render;
    if (slabbed && o.method == "ddt") {
      const int needed =
          tile_margin_needed(vs.iterations + vs.presmooth_iterations, region) + smoothing_reach;
      const bool cut_short = (lo > 0 && a0 - lo < needed) || (hi < units && hi - a1 < needed);
      if (cut_short) {
        margin = round_up(needed, region);
        ++local.reruns;
        if (options.log)
          options.log("tile at slice " + std::to_string(a0) + ": " + std::to_string(vs.iterations) + " + " +
                      std::to_string(vs.presmooth_iterations) + " phases need a margin of " + std::to_string(needed) +
                      " slices; run again with " + std::to_string(margin));
        continue;
      }
    }
    ++local.tiles;
    local.simplices = std::max(local.simplices, vs.tetrahedra);

    const bool last = a1 == units;
    const int g_end = scale * a1 + (last && node ? 1 : 0);
    t0 = Clock::now();
    for (int g = scale * a0; g < g_end; ++g) {
      write(result.voxels.data() + static_cast<std::size_t>(g - scale * lo) * out_slice, g);
      if (tiling.progress) tiling.progress->add(1);
    }
    local.seconds_write += seconds_since(t0);
    if (last) break;
    a0 = a1;
  }
  local.margin_slices = margin;
  if (stats) *stats = local;
}

}  // namespace ddt
