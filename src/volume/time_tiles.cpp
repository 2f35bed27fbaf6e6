#include "volume/time_tiles.hpp"

#include "util/error.hpp"
#include "util/timing.hpp"

#include <algorithm>
#include <deque>

namespace ddt {

int time_tiled_output_steps(int steps, int time_scale) { return (steps - 1) * time_scale + 1; }

int time_tile_steps(long long samples_per_step, int margin_steps) {
  const long long steps = std::max(1LL, (1LL << 22) / std::max(1LL, samples_per_step));
  return static_cast<int>(std::max(1LL, steps - 2LL * std::max(0, margin_steps)));
}

void upscale_in_time_tiles(const std::array<int, 3>& in, const std::array<int, 3>& out, int channels, int steps,
                           int time_scale, const VolumeUpscaleOptions& options, const TimeTiling& tiling,
                           const std::function<void(int, float*)>& read,
                           const std::function<void(const float*, int)>& write, TimeTilingStats* stats) {
  if (steps < 1) throw Error("the sequence has no frames");
  for (int a = 0; a < 3; ++a)
    if (in[a] < 1 || out[a] < 1) throw Error("the frames and the output must be at least 1x1");
  if (channels < 1) throw Error("the frames are empty");
  if (time_scale < 1) throw Error("the time scale must be a whole number of at least 1");
  if (tiling.margin_steps < 0) throw Error("the time margin must be at least 0 steps");
  const std::size_t in_step = std::size_t(in[0]) * in[1] * in[2] * channels;
  const std::size_t out_step = std::size_t(out[0]) * out[1] * out[2] * channels;
  const int tile = tiling.tile_steps > 0 ? tiling.tile_steps
                                         : time_tile_steps(static_cast<long long>(in_step / channels), tiling.margin_steps);
  const int margin = tiling.margin_steps;
  if (tiling.progress) tiling.progress->begin("enlarge", time_tiled_output_steps(steps, time_scale));

  TimeTilingStats local;
  std::deque<std::vector<float>> cache;  // input steps cache_first, cache_first + 1, ...
  int cache_first = 0;
  VolumeUpscaleOptions o = options;
  o.node_centred[3] = true;
  o.presmooth[3] = 0;

  for (int a0 = 0;; a0 += tile) {
    // The tile's own input steps are a0..a1 (the output steps from s * a0
    // up to, not including, s * a1; the last tile's include it); lo..hi
    // adds the margins.
    const int a1 = std::min(a0 + tile, steps - 1);
    const int lo = std::max(0, a0 - margin), hi = std::min(steps - 1, a1 + margin);
    while (!cache.empty() && cache_first < lo) cache.pop_front(), ++cache_first;
    if (cache.empty()) cache_first = lo;
    auto t0 = Clock::now();
    while (cache_first + static_cast<int>(cache.size()) <= hi) {
      cache.emplace_back(in_step);
      read(cache_first + static_cast<int>(cache.size()) - 1, cache.back().data());
    }
    local.seconds_read += seconds_since(t0);

    const int count = hi - lo + 1;
    Volume part({in[0], in[1], in[2], count}, channels, 0.0f);
    for (int k = 0; k < count; ++k)
      std::copy(cache[std::size_t(lo - cache_first + k)].begin(), cache[std::size_t(lo - cache_first + k)].end(),
                part.voxels.begin() + static_cast<std::ptrdiff_t>(k * in_step));
    VolumeUpscaleStats vs;
    const Volume result =
        upscale_volume(part, {out[0], out[1], out[2], time_tiled_output_steps(count, time_scale)}, o, &vs);
    ++local.tiles;
    local.flips += vs.flips.total() + vs.planar_flips + vs.presmooth_flips;
    local.simplices = std::max(local.simplices, vs.tetrahedra);
    local.seconds_triangulate += vs.seconds_triangulate;
    local.seconds_optimize += vs.seconds_optimize;
    local.seconds_render += vs.seconds_render;

    const bool last = a1 == steps - 1;
    const int g_end = last ? time_scale * a1 : time_scale * a1 - 1;
    t0 = Clock::now();
    for (int g = time_scale * a0; g <= g_end; ++g) {
      write(result.voxels.data() + std::size_t(g - time_scale * lo) * out_step, g);
      if (tiling.progress) tiling.progress->add(1);
    }
    local.seconds_write += seconds_since(t0);
    if (last) break;
  }
  if (stats) *stats = local;
}

}  // namespace ddt
