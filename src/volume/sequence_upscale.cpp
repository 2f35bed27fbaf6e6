#include "volume/sequence_upscale.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace ddt {

int sequence_output_frames(int frames, double time_scale) { return tiled_output_slices(frames, time_scale, true); }

int sequence_tile_frames(int width, int height, int margin_frames) {
  return default_tile_slices(static_cast<long long>(width) * height, margin_frames);
}

void upscale_sequence(int frames, int width, int height, int channels, const std::function<Image(int)>& read,
                      int out_width, int out_height, double time_scale, const SequenceUpscaleOptions& options,
                      const std::function<void(Image, int)>& write, SequenceUpscaleStats* stats) {
  if (frames < 1) throw Error("the sequence has no frames");
  if (!(time_scale > 0) || !(time_scale <= 1024)) throw Error("the time scale must be a number in (0, 1024]");
  VolumeTiling tiling;
  tiling.tile_slices = options.tile_frames;
  tiling.margin_slices = options.margin_frames;
  tiling.exact = options.exact_tiles;
  tiling.progress = options.progress;
  // A whole scale is read from the sizes (the same arithmetic as the
  // untiled volume); any other is given to the tiler.
  if (time_scale != std::floor(time_scale)) tiling.axis_scale = time_scale;
  VolumeUpscaleOptions volume = options.volume;
  volume.node_centred[3] = true;  // frames are instants
  volume.presmooth[3] = 0;
  auto read_step = [&](int k, float* samples) {
    const Image f = read(k);
    if (f.width != width || f.height != height || f.channels != channels)
      throw Error("frame " + std::to_string(k) + " is " + std::to_string(f.width) + "x" + std::to_string(f.height) +
                  "x" + std::to_string(f.channels) + ", not " + std::to_string(width) + "x" + std::to_string(height) +
                  "x" + std::to_string(channels));
    std::copy(f.pixels.begin(), f.pixels.end(), samples);
  };
  auto write_step = [&](const float* samples, int k) {
    Image frame(out_width, out_height, channels);
    std::copy(samples, samples + frame.pixels.size(), frame.pixels.begin());
    write(std::move(frame), k);
  };
  upscale_in_tiles({width, height, 1, frames}, {out_width, out_height, 1, sequence_output_frames(frames, time_scale)},
                   channels, volume, tiling, read_step, write_step, stats);
}

}  // namespace ddt
