#pragma once
// ddt::upscale_in_time_tiles — a series (x, y, z, t; node-centred time)
// enlarged by upscale_volume in tiles over time, so the mesh held at once
// is that of one tile: `tile_steps` input steps plus `margin_steps` on
// either side (read once, kept while the next tile needs them). Each tile's
// own output steps are handed to `write` in order and freed. Tiles change
// the result only near their joins, where a flip sequence reaches through
// the margin (docs/sequences.md measures it). Image sequences
// (sequence_upscale.hpp) are series of one z-slice.
//
// Steps: T input steps at time scale s (a whole number) become
// (T - 1) * s + 1, output step s * k is input step k.
// A step is nx * ny * nz * channels floats, channels fastest, then x, y, z.
//
// Errors: throws ddt::Error (bad sizes or scales, and upscale_volume's).

#include "util/progress.hpp"
#include "volume/volume_upscale.hpp"

#include <array>
#include <functional>
#include <vector>

namespace ddt {

struct TimeTiling {
  int tile_steps = 0;     // input steps per tile; 0: time_tile_steps()
  int margin_steps = 4;   // extra input steps reconstructed on either side of a tile
  Progress* progress = nullptr;  // "enlarge" stage, in output steps
};

struct TimeTilingStats {
  int tiles = 0;
  long long flips = 0;       // both passes of the graduated optimization
  long long simplices = 0;   // of the largest tile
  double seconds_read = 0, seconds_triangulate = 0, seconds_optimize = 0, seconds_render = 0, seconds_write = 0;
};

// The default tile: about 2^22 input samples (a mesh of about 2 GB) with its
// margins, at least one step beyond them.
int time_tile_steps(long long samples_per_step, int margin_steps);

// Output steps of T input steps at time scale s: (T - 1) * s + 1.
int time_tiled_output_steps(int steps, int time_scale);

// in, out: space sizes (x, y, z); options.node_centred[3] and presmooth[3]
// are set here (time: node-centred, not smoothed).
void upscale_in_time_tiles(const std::array<int, 3>& in, const std::array<int, 3>& out, int channels, int steps,
                           int time_scale, const VolumeUpscaleOptions& options, const TimeTiling& tiling,
                           const std::function<void(int step, float* samples)>& read,
                           const std::function<void(const float* samples, int step)>& write,
                           TimeTilingStats* stats = nullptr);

}  // namespace ddt
