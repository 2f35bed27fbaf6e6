#include "volume/sequence_upscale.hpp"

#include "util/error.hpp"
#include "util/timing.hpp"

#include <algorithm>
#include <cstring>
#include <deque>
#include <string>

namespace ddt {

int sequence_output_frames(int frames, int time_scale) { return (frames - 1) * time_scale + 1; }

int sequence_tile_frames(int width, int height, int margin_frames) {
  const long long per_frame = std::max(1LL, static_cast<long long>(width) * height);
  const long long frames = std::max(1LL, (1LL << 22) / per_frame);
  return static_cast<int>(std::max(1LL, frames - 2LL * std::max(0, margin_frames)));
}

void upscale_sequence(int frames, int width, int height, int channels, const std::function<Image(int)>& read,
                      int out_width, int out_height, int time_scale, const SequenceUpscaleOptions& options,
                      const std::function<void(Image, int)>& write, SequenceUpscaleStats* stats) {
  if (frames < 1) throw Error("the sequence has no frames");
  if (width < 1 || height < 1 || channels < 1) throw Error("the frames are empty");
  if (out_width < 1 || out_height < 1) throw Error("the output frames must be at least 1x1");
  if (time_scale < 1) throw Error("the time scale must be a whole number of at least 1");
  if (options.margin_frames < 0) throw Error("the time margin must be at least 0 frames");
  const int tile = options.tile_frames > 0 ? options.tile_frames : sequence_tile_frames(width, height, options.margin_frames);
  const int margin = options.margin_frames;
  const int out_frames = sequence_output_frames(frames, time_scale);
  const std::size_t in_frame = static_cast<std::size_t>(width) * height * channels;
  const std::size_t out_frame = static_cast<std::size_t>(out_width) * out_height * channels;
  if (options.progress) options.progress->begin("enlarge", out_frames);

  SequenceUpscaleStats local;
  std::deque<Image> cache;  // input frames cache_first, cache_first + 1, ...
  int cache_first = 0;
  VolumeUpscaleOptions volume_options = options.volume;
  volume_options.node_centred = {false, false, true};

  for (int a0 = 0;; a0 += tile) {
    // The tile's own input frames are a0..a1 (the output frames from
    // s * a0 up to, not including, s * a1; the last tile's include it);
    // lo..hi adds the margins.
    const int a1 = std::min(a0 + tile, frames - 1);
    const int lo = std::max(0, a0 - margin), hi = std::min(frames - 1, a1 + margin);
    while (!cache.empty() && cache_first < lo) cache.pop_front(), ++cache_first;
    if (cache.empty()) cache_first = lo;
    auto t0 = Clock::now();
    while (cache_first + static_cast<int>(cache.size()) <= hi) {
      const int number = cache_first + static_cast<int>(cache.size());
      Image f = read(number);
      if (f.width != width || f.height != height || f.channels != channels)
        throw Error("frame " + std::to_string(number) + " is " + std::to_string(f.width) + "x" +
                    std::to_string(f.height) + "x" + std::to_string(f.channels) + ", not " + std::to_string(width) +
                    "x" + std::to_string(height) + "x" + std::to_string(channels));
      cache.push_back(std::move(f));
    }
    local.seconds_read += seconds_since(t0);

    const int count = hi - lo + 1;
    Volume in(width, height, count, channels, 0.0f);
    for (int k = 0; k < count; ++k)
      std::memcpy(in.voxels.data() + k * in_frame, cache[static_cast<std::size_t>(lo - cache_first + k)].pixels.data(),
                  in_frame * sizeof(float));
    VolumeUpscaleStats vs;
    const Volume out = upscale_volume(in, out_width, out_height, sequence_output_frames(count, time_scale),
                                      volume_options, &vs);
    ++local.tiles;
    local.flips += vs.flips.total() + vs.planar_flips + vs.presmooth_flips;
    local.tetrahedra = std::max(local.tetrahedra, vs.tetrahedra);
    local.seconds_triangulate += vs.seconds_triangulate;
    local.seconds_optimize += vs.seconds_optimize;
    local.seconds_render += vs.seconds_render;

    const bool last = a1 == frames - 1;
    const int g_end = last ? time_scale * a1 : time_scale * a1 - 1;
    t0 = Clock::now();
    for (int g = time_scale * a0; g <= g_end; ++g) {
      Image frame(out_width, out_height, channels);
      const std::size_t j = static_cast<std::size_t>(g - time_scale * lo);
      std::memcpy(frame.pixels.data(), out.voxels.data() + j * out_frame, out_frame * sizeof(float));
      write(std::move(frame), g);
      if (options.progress) options.progress->add(1);
    }
    local.seconds_write += seconds_since(t0);
    if (last) break;
  }
  if (stats) *stats = local;
}

}  // namespace ddt
