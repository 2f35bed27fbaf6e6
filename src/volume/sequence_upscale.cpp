#include "volume/sequence_upscale.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace ddt {

int sequence_output_frames(int frames, double time_scale) { return tiled_output_slices(frames, time_scale, true); }

int sequence_tile_frames(int width, int height, int margin_frames) {
  return default_tile_slices(static_cast<long long>(width) * height, margin_frames);
}

void set_motion(SequenceUpscaleOptions& options, const std::string& text) {
  options.volume.time_shear = {0, 0};
  options.volume.time_zoom = 0;
  if (text == "auto" || text == "off") {
    options.shear_dominant_motion = text == "auto";
    return;
  }
  double dx = 0, dy = 0, zoom = 1;
  char rest = 0;
  const bool with_zoom = std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &dx, &dy, &zoom, &rest) == 3;
  const bool shift_only = !with_zoom && std::sscanf(text.c_str(), "%lf,%lf%c", &dx, &dy, &rest) == 2;
  if ((!with_zoom && !shift_only) || !std::isfinite(dx) || !std::isfinite(dy) || std::abs(dx) > 1000 ||
      std::abs(dy) > 1000 || !(zoom >= 0.5 && zoom <= 2))
    throw Error("--motion must be auto, off, DX,DY or DX,DY,ZOOM (pixels a frame, at most 1000; ZOOM the scale a "
                "frame about the centre, 0.5 to 2), not '" + text + "'");
  options.shear_dominant_motion = false;
  // To 1/8 pixel, as the estimate is: the sheared positions are then exact
  // in doubles wherever a tile's frames start, so exact tiles stay the
  // untiled result bit for bit (a shear of 0.3 rounds differently per tile).
  options.volume.time_shear = {to_eighth_pixel(dx), to_eighth_pixel(dy)};
  options.volume.time_zoom = to_zoom_step(zoom - 1);
}

std::string motion_text(const SequenceUpscaleOptions& options) {
  if (options.shear_dominant_motion) return "auto";
  const auto [dx, dy] = options.volume.time_shear;
  const double zoom = options.volume.time_zoom;
  if (dx == 0 && dy == 0 && zoom == 0) return "off";
  char text[120];
  if (zoom == 0)
    std::snprintf(text, sizeof text, "%g,%g", dx, dy);
  else
    std::snprintf(text, sizeof text, "%g,%g,%.17g", dx, dy, 1 + zoom);
  return text;
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
  if (volume.time_zoom != 0 && std::abs((frames - 1) * std::log1p(volume.time_zoom)) > std::log(max_sequence_zoom)) {
    char line[200];
    std::snprintf(line, sizeof line, "--motion: a zoom of %g a frame over %d frames is a factor over %g; give a zoom nearer 1",
                  1 + volume.time_zoom, frames, max_sequence_zoom);
    throw Error(line);
  }
  DominantMotion motion;
  if (options.shear_dominant_motion && volume.method == VolumeMethod::ddt && frames > 1) {
    motion = dominant_motion(frames, options.motion_frames ? options.motion_frames : read);
    volume.time_shear = {motion.dx, motion.dy};
    volume.time_zoom = motion.zoom;
    if (volume.log) {
      char line[300];
      if (motion.zoom != 0)
        std::snprintf(line, sizeof line,
                      "motion: %d of %d frame pairs agree on a zoom of %+.2f %% and (%.2f, %.2f) px a frame: the "
                      "mesh starts along it",
                      motion.zoom_agreeing, motion.pairs, 100 * motion.zoom, motion.dx, motion.dy);
      else if (motion.slow_zoom)
        std::snprintf(line, sizeof line,
                      "motion: %d of %d frame pairs agree on a zoom of %+.2f %%, a pixel or less a frame at the "
                      "edges: the lattice's mesh",
                      motion.zoom_agreeing, motion.pairs, 100 * motion.median_zoom);
      else
        std::snprintf(line, sizeof line, "motion: %d of %d frame pairs agree on (%.2f, %.2f) px a frame: %s",
                      motion.agreeing, motion.pairs, motion.median_dx, motion.median_dy,
                      motion.found  ? "the mesh starts sheared along it"
                      : motion.slow ? "a pixel or less a frame, the lattice's mesh"
                                    : "no dominant motion, the lattice's mesh");
      volume.log(line);
    }
  }
  const auto [dx, dy] = volume.time_shear;
  const bool whole_shift = (dx != 0 || dy != 0) && dx == std::round(dx) && dy == std::round(dy);
  const bool along_motion = volume.time_zoom != 0 || whole_shift;
  const double narrower = options.presmooth_along_motion;
  if ((along_motion || motion.slow) && narrower >= 0 && volume.method == VolumeMethod::ddt &&
      std::max(volume.presmooth[0], volume.presmooth[1]) > narrower) {
    volume.presmooth[0] = volume.presmooth[1] = narrower;
    if (volume.log) {
      char line[160];
      std::snprintf(line, sizeof line, "presmooth: sigma %g px in space (%s)", narrower,
                    volume.time_zoom != 0 ? "the mesh starts along the zoom"
                    : whole_shift         ? "the mesh starts along the whole-pixel shift"
                                          : "the frames move by a pixel or less");
      volume.log(line);
    }
  }
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
  if (stats) stats->motion = motion;
}

}  // namespace ddt
