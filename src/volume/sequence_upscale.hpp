#pragma once
// ddt::upscale_sequence — frame-rate upsampling (and enlargement) of an
// image sequence as one 2D + time field: the frames are the slices of a
// volume (x, y, t), triangulated into tetrahedra and optimized by the
// generalized Lawson procedure like a volume (volume_upscale.hpp), all
// channels on one mesh. A moving edge is a slanted surface in (x, y, t);
// tetrahedra that align with it interpolate along the motion, without
// per-pixel optical flow (at most one translation for the whole sequence,
// dominant_motion.hpp, shears the initial mesh) and without the double
// images of blended frames.
//
// Time is node-centred (frames are instants): output frame g samples the
// field at the instant g / s of the input's frames (0 the first). At a
// whole time scale s, T input frames become (T - 1) * s + 1 output frames
// and output frame s * k is input frame k (bit for bit at odd spatial
// scales and at scale 1). Any s > 0 works: a frame-rate conversion from 24
// to 60 frames a second is s = 2.5, and makes floor((T - 1) * s) + 1
// frames. Space follows the pixel convention (image.hpp).
//
// Memory is bounded by tiling over time (volume_tiles.hpp: a sequence is a
// series of one z-slice): the frames are reconstructed in tiles of
// `tile_frames` input frames plus `margin_frames` on either side; each
// tile's output frames are handed to the sink in order and freed. The
// joins differ a little from the untiled result (docs/sequences.md) unless
// `exact_tiles`: then the margins are whole slabs of the optimizer's
// schedule, widened as its phases need (volume_tiles.hpp), which on large
// frames costs several times the work. Off by default, since sequences
// tile by default: a tile holds about 2^22 input pixels.
//
// Errors: throws ddt::Error (bad sizes or scales, unknown method or cost,
// too many channels, a frame source that fails).

#include "util/image.hpp"
#include "util/progress.hpp"
#include "volume/dominant_motion.hpp"
#include "volume/volume_tiles.hpp"
#include "volume/volume_upscale.hpp"

#include <functional>
#include <string>

namespace ddt {

// The sequences' defaults (measured in docs/sequences.md): the paper's
// linear render (on moving edges above the cubic one, whose slopes along
// time come from frames a whole motion apart), and the graduated
// optimization on frames smoothed in space by a Gaussian of sigma 1 pixel
// (a moving edge's flips start on a gentler cost; not across time, where
// the samples are a motion apart), and slow fine texture kept paired
// along time (slow_texture.hpp).
inline VolumeUpscaleOptions sequence_volume_defaults() {
  VolumeUpscaleOptions o;
  o.render = Render::linear;
  o.presmooth = {1.0, 1.0, 0.0};
  o.keep_slow_texture = true;
  return o;
}

struct SequenceUpscaleOptions {
  // method, cost, render, slopes, tolerance, log (node_centred set here)
  VolumeUpscaleOptions volume = sequence_volume_defaults();
  int tile_frames = 0;          // input frames per tile; 0: sequence_tile_frames()
  int margin_frames = 4;        // extra input frames reconstructed on either side of a tile (at least)
  bool exact_tiles = false;     // widen the margins until the tiles equal the untiled result
  // Shear the initial mesh along the dominant motion of the whole sequence
  // (dominant_motion.hpp), when it has one; volume.time_shear is then set
  // from it. Off: volume.time_shear as given (0, 0: the lattice's mesh).
  bool shear_dominant_motion = true;
  // The graduated optimization's sigma in space (pixels) at most, when the
  // mesh starts along a zoom, or along a shift of whole pixels a frame
  // (found, or given as volume.time_zoom or time_shear): the flips then have only
  // the departures from that motion to find, which a narrower smoothing
  // serves better; along a fractional shift it did not. And when the
  // frames agree on a motion of a pixel or less a frame
  // (DominantMotion::slow): the flips have no far pairing to reach, and
  // the wider smoothing blurred slow photographs (docs/sequences.md, "The
  // graduated optimization"). Negative: volume.presmooth whatever the mesh
  // (a sigma the user gave).
  double presmooth_along_motion = 0.5;
  // Where dominant_motion reads its frames, when not `read` (a source that
  // `read` cannot rewind, such as a video: a second reader). Frames are
  // asked for in increasing order.
  std::function<Image(int)> motion_frames;
  Progress* progress = nullptr;  // "enlarge" stage, in output frames
};

struct SequenceUpscaleStats : VolumeTilingStats {
  DominantMotion motion;  // what shear_dominant_motion found
};

// The command line's and the Python module's --motion: "auto" (shear
// along the dominant motion, the default), "off" (the lattice's mesh), or
// "DX,DY" (shear by that many pixels a frame). Errors: ddt::Error naming
// the three forms.
void set_motion(SequenceUpscaleOptions& options, const std::string& text);
std::string motion_text(const SequenceUpscaleOptions& options);

// The default tile: about 2^22 input samples (mesh and output of a few GB
// at most) including its margins, at least one frame beyond them.
int sequence_tile_frames(int width, int height, int margin_frames);

// Output frames of T input frames at time scale s: (T - 1) * s + 1 at a
// whole s, floor((T - 1) * s) + 1 as a rule (the last at or before the
// last input frame).
int sequence_output_frames(int frames, double time_scale);

// `frames` input frames of width x height x channels, read on demand by
// read(number) (0-based); written by write(frame, number) in order of
// number, each out_width x out_height.
void upscale_sequence(int frames, int width, int height, int channels, const std::function<Image(int)>& read,
                      int out_width, int out_height, double time_scale, const SequenceUpscaleOptions& options,
                      const std::function<void(Image, int)>& write, SequenceUpscaleStats* stats = nullptr);

}  // namespace ddt
