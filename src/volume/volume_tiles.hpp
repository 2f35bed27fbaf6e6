#pragma once
// ddt::upscale_in_tiles — a volume enlarged by upscale_volume in tiles
// along its last axis (time for a series, z for a 3D volume; image
// sequences, sequence_upscale.hpp, are series of one z-slice), so the mesh
// held at once is that of one tile: `tile_slices` input slices plus
// margins on either side (read once, kept while the next tile needs them).
// Each tile's own output slices are handed to `write` in order and freed.
//
// Exact tiles (the default): the result is the untiled one bit for bit.
// The Lawson procedure runs in slabs of R slices (core/lawson.hpp's region
// schedule, R = options.region_slices or volume_region_slices of the whole
// volume), which every tile shares: tiles and margins are whole slabs, so a
// tile's slabs are the untiled run's. Within a phase no flip crosses a
// slab; each phase moves the slabs by half of one. So what a cut changes
// reaches at most (phases + 1) * ceil(R / 2) + 2 slices into the tile
// (tile_margin_needed); a tile whose margin proves narrower than that for
// the phases it ran (both passes of the graduated optimization counted) is
// run again with the margin widened, and the tiles after it keep the wider
// margin. Where the whole volume is one slab (at most about 2^19
// simplices, options.region_slices unset) it is one tile.
// Inexact tiles (exact = false): margins as given, the result differs near
// the joins (docs/sequences.md measures it).
//
// Along the tiled axis, at scale s: node-centred, output slice g samples
// the instant g / s (output slice s k is input slice k; n input slices
// become (n - 1) s + 1 at a whole s, floor((n - 1) s) + 1 as a rule),
// cell-centred, output slice G samples (G + 0.5) / s (n s slices). The
// scale is a whole number from the sizes unless VolumeTiling::axis_scale
// gives it. Each tile draws only its own output slices (a window of the
// whole output's grid, VolumeUpscaleOptions::last_axis).
// A slice is the product of the other axes' sizes times channels floats,
// channels fastest, then x, y (, z).
//
// Errors: throws ddt::Error (bad sizes or scales, and upscale_volume's).

#include "util/progress.hpp"
#include "volume/volume_upscale.hpp"

#include <array>
#include <functional>
#include <vector>

namespace ddt {

struct VolumeTiling {
  int tile_slices = 0;     // input slices per tile; 0: default_tile_slices()
  int margin_slices = 4;   // slices reconstructed on either side of a tile (exact: at least this, whole slabs)
  bool exact = true;       // widen the margins until every tile equals the untiled result
  // The tiled axis' scale, output samples per input sample; 0: from the
  // sizes, a whole number. Otherwise any scale > 0 (fractional frame
  // rates), output sample g at position g / scale as above.
  double axis_scale = 0;
  Progress* progress = nullptr;  // "enlarge" stage, in output slices
};

struct VolumeTilingStats {
  int tiles = 0;
  int region_slices = 0;     // slab of the Lawson schedule every tile used (exact tiles)
  int margin_slices = 0;     // the margin the last tile ran with (widened as needed)
  int reruns = 0;            // tiles run again with a wider margin
  long long flips = 0;       // both passes of the graduated optimization
  long long simplices = 0;   // of the largest tile
  double seconds_read = 0, seconds_triangulate = 0, seconds_optimize = 0, seconds_render = 0, seconds_write = 0;
};

// The default tile: about 2^22 input samples (a mesh of about 2 GB) with its
// margins, at least one slice beyond them.
int default_tile_slices(long long samples_per_slice, int margin_slices);

// Output slices of n input slices at scale s: floor((n - 1) s) + 1
// node-centred (the last at or before the last input instant), round(n s)
// cell-centred.
int tiled_output_slices(int slices, double scale, bool node_centred);

// Slices of margin a cut side needs after `phases` phases of slabs of R
// slices (the graduated optimization's two passes summed).
int tile_margin_needed(int phases, int region_slices);

// in, out: sizes x, y, z, t; the last axis of more than one input sample
// (t for a series, else z) is tiled, and its output size must be a whole
// scale of the input's (as above, by options.node_centred).
void upscale_in_tiles(const std::array<int, 4>& in, const std::array<int, 4>& out, int channels,
                      const VolumeUpscaleOptions& options, const VolumeTiling& tiling,
                      const std::function<void(int slice, float* samples)>& read,
                      const std::function<void(const float* samples, int slice)>& write,
                      VolumeTilingStats* stats = nullptr);

}  // namespace ddt
