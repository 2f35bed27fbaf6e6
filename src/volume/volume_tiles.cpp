#include "volume/volume_tiles.hpp"

#include "util/error.hpp"
#include "util/timing.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

namespace ddt {
namespace {

int round_up(int value, int multiple) { return (value + multiple - 1) / multiple * multiple; }

// The sizes the mesh reconstruction sees, x, y, z, t order kept.
std::array<int, 4> mesh_problem_size(const std::array<int, 4>& in) {
  const std::array<bool, 4> keep = mesh_problem_axes(in);
  std::array<int, 4> size{1, 1, 1, 1};
  for (int a = 0, j = 0; a < 4; ++a)
    if (keep[a]) size[j++] = in[a];
  return size;
}

}  // namespace

int tiled_output_slices(int slices, double scale, bool node_centred) {
  const double count = node_centred ? std::floor((slices - 1) * scale + 1e-9) + 1 : std::round(slices * scale);
  return static_cast<int>(std::clamp(count, 1.0, 2147483647.0));
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
  if (!is_mesh_method(options.method))
    throw Error(std::string("tiles are for the ddt and delaunay methods, not ") + to_string(options.method));
  const int axis = in[3] > 1 ? 3 : 2;
  const bool node = options.node_centred[axis] && in[axis] > 1;
  const int n = in[axis];
  const std::array<int, 4> problem = mesh_problem_size(in);
  // A 3D (or 4D) mesh: windows along the last axis, slabs (a thin axis among
  // three makes it the 2D method's).
  const bool mesh_problem = problem[0] > 1 && problem[1] > 1 && problem[2] > 1;
  // Units tiled: the n - 1 intervals between node-centred slices, or the n cells.
  const int units = node ? n - 1 : n;
  double scale = tiling.axis_scale;
  if (scale <= 0) {
    scale = node ? double(out[axis] - 1) / std::max(1, n - 1) : double(out[axis]) / n;
    if (n > 1 && (scale < 1 || scale != std::floor(scale)))
      throw Error(std::string("tiles need a whole scale along ") + (axis == 3 ? "time" : "z") + " (" +
                  (node ? "(n - 1) * S + 1" : "n * S") + " output slices)");
  } else if (!mesh_problem && n > 1) {
    throw Error("a fractional scale along the tiled axis needs at least 2 samples on two other axes");
  }
  if (n == 1 || !mesh_problem) {  // nothing to tile: enlarged whole
    Volume whole(in, channels, 0.0f);
    const std::size_t slice = whole.voxels.size() / n;
    for (int k = 0; k < n; ++k) read(k, whole.voxels.data() + k * slice);
    const Volume result = upscale_volume(whole, out, options);
    const std::size_t out_slice = result.voxels.size() / out[axis];
    for (int g = 0; g < out[axis]; ++g) write(result.voxels.data() + g * out_slice, g);
    if (stats) *stats = VolumeTilingStats{}, stats->tiles = 1;
    return;
  }
  // Output sample g sits at g / scale (node-centred: instants, input slice
  // k at k) or (g + 0.5) / scale (cells: input slice k spans [k, k + 1));
  // the first at or after u:
  const double half = node ? 0.0 : 0.5;
  auto first_output_at = [&](double u) {
    return static_cast<int>(std::clamp(std::ceil(u * scale - half - 1e-9), 0.0, double(out[axis])));
  };

  std::size_t in_slice = static_cast<std::size_t>(channels), out_slice = static_cast<std::size_t>(channels);
  for (int a = 0; a < axis; ++a) in_slice *= in[a], out_slice *= out[a];
  const bool slabbed = tiling.exact;
  int tile = tiling.tile_slices > 0 ? tiling.tile_slices
                                    : default_tile_slices(static_cast<long long>(in_slice / channels), tiling.margin_slices);
  tile = std::min(tile, units);  // and so are the margins below: no overflow on rounding up
  int margin = std::min(tiling.margin_slices, units);
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
    // The tile's own units are [a0, a1) (and its output samples those at
    // positions in it; the last tile's include the end); lo..hi adds the
    // margins; its input slices are lo..hi (node-centred) or lo..hi - 1.
    const int a1 = std::min(a0 + tile, units);
    const int lo = std::max(0, a0 - margin), hi = std::min(units, a1 + margin);
    const int slices = node ? hi - lo + 1 : hi - lo;
    const bool last = a1 == units;
    const int g0 = first_output_at(a0), g1 = last ? out[axis] : first_output_at(a1);
    while (!cache.empty() && cache_first < lo) cache.pop_front(), ++cache_first;
    if (cache.empty()) cache_first = lo;
    while (cache_first > lo) {  // a margin widened past what was kept
      cache.emplace_front(in_slice);
      read(--cache_first, cache.front().data());
    }
    auto t0 = Clock::now();
    while (cache_first + static_cast<int>(cache.size()) < lo + slices) {
      cache.emplace_back(in_slice);
      read(cache_first + static_cast<int>(cache.size()) - 1, cache.back().data());
    }
    local.seconds_read += seconds_since(t0);
    if (g1 <= g0 && !last) {  // a tile between two output samples (scale < 1): nothing of its own
      a0 = a1;
      continue;
    }

    std::array<int, 4> part_size = in, part_out = out;
    part_size[axis] = slices;
    part_out[axis] = std::max(1, g1 - g0);
    Volume part(part_size, channels, 0.0f);
    for (int k = 0; k < slices; ++k) {
      const std::vector<float>& slice = cache[static_cast<std::size_t>(lo - cache_first + k)];
      std::copy(slice.begin(), slice.end(), part.voxels.begin() + static_cast<std::ptrdiff_t>(k * in_slice));
    }
    // The part draws the tile's own output samples only: a window of the
    // whole output's grid, counted from the part's first input slice.
    o.last_axis.scale = scale;
    o.last_axis.first = g0 - lo * scale;
    o.time_origin = options.time_origin + lo;
    VolumeUpscaleStats vs;
    const Volume result = upscale_volume(part, part_out, o, &vs);
    local.flips += vs.flips.total() + vs.planar_flips + vs.presmooth_flips;
    local.seconds_triangulate += vs.seconds_triangulate;
    local.seconds_optimize += vs.seconds_optimize;
    local.seconds_render += vs.seconds_render;
    if (slabbed && o.method == VolumeMethod::ddt) {
      const int needed = tile_margin_needed(vs.iterations + vs.presmooth_iterations, region) + smoothing_reach;
      if ((lo > 0 && a0 - lo < needed) || (hi < units && hi - a1 < needed)) {
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
    t0 = Clock::now();
    for (int g = g0; g < g1; ++g) {
      write(result.voxels.data() + static_cast<std::size_t>(g - g0) * out_slice, g);
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
