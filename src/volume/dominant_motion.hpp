#pragma once
// ddt::dominant_motion — the translation that carries most of an image
// sequence from one frame to the next (a camera pan, one object moving over
// a flat background), found by matching whole frames; or, where no one
// translation does, a zoom about the frame's centre with a translation (a
// camera zooming), found by matching blocks.
//
// Why: the space-time mesh starts as the Delaunay triangulation of the
// sample lattice, which pairs every sample with the same pixel in the next
// frame. The flips then tilt it towards the motion, but greedily: a pairing
// several pixels along the motion needs long slanted tetrahedra that no
// sequence of improving flips reaches, so a rim that slides along itself
// is paired with its nearest point in the next frame instead of the point
// the motion carries it to (docs/sequences.md, "Dominant motion"). Starting
// from the Delaunay triangulation of the samples sheared by the dominant
// motion (volume_upscale.cpp) puts those tetrahedra in the initial mesh;
// the flips then work from there, for whatever does not move with it.
//
// Per pair of consecutive frames (at most max_pairs pairs, evenly spaced):
// the mean absolute difference, channels averaged, of frame t at (x, y) and
// frame t + 1 at (x + dx, y + dy) over their overlap (at least half the
// frame on each axis) is minimized over whole shifts, coarse to fine (2x2
// box pyramid down to about 32 pixels, an exhaustive search of +-4 there,
// +-1 at each finer level), then refined to a fraction of a pixel by the
// vertex of the quadratic through the mean squared differences at the 3x3
// shifts around it. A pair is explained when its best difference is at
// most max_residual_share of the difference without a shift (identical
// frames: the zero shift, explained).
//
// The result is the median shift of the pairs, kept when at least
// min_agreeing_share of the pairs are explained and within 0.5 pixel of it
// and it moves more than min_shift pixels on some axis (slower motion is
// what the lattice already pairs well: slow_texture.hpp); else zero (and
// `slow` says whether the pairs agreed on that slower motion). It is
// rounded to 1/8 pixel, so that the mesh does not hang on the estimate's
// last bits (a whole shift stays whole).
//
// The zoom model: frame t + 1 at x + zoom (x - c) + d matches frame t at x
// (c the frame's centre; x, c in pixels, a pixel's centre at +0.5). Tried
// only where the whole-frame translation is not found. In each pair whose
// translation does not explain it, a zoom_blocks x zoom_blocks grid of
// blocks is matched alone (the same coarse-to-fine search, from the
// coarsest level where a block is 16 pixels), blocks with too little
// texture skipped; (zoom, d) is the least-squares fit of the blocks'
// shifts, fitted again over the blocks within 0.5 pixel of it, and the
// pair is explained when those are min_agreeing_share of the blocks (at
// least min_zoom_blocks). The medians of zoom and d are kept when
// min_agreeing_share of the pairs are explained and within 0.5 pixel of
// them at the farthest corner, when the zoom alone moves the frame's edges
// by more than min_shift a frame (slower, the translation's rules decide),
// and when the zoom held over the whole sequence stays within a
// factor max_total_zoom; zoom is rounded to 2^-16, d to 1/8 pixel.
//
// frame(k) gives input frame k (0-based; any channels); the frames of the
// pairs are asked for in increasing order, each once, so a source that
// only reads forward (a video) serves them.
// Errors: ddt::Error on frames of different sizes; what frame() throws.

#include "util/image.hpp"

#include <cmath>
#include <functional>

namespace ddt {

// A shift a frame to 1/8 pixel: the estimate's result, a given --motion and
// the shear the mesh is built with (volume_upscale.cpp), whose sheared
// positions are then exact in doubles at every frame.
inline double to_eighth_pixel(double shift) { return std::round(shift * 8) / 8; }
// A zoom a frame (relative, 0.02: 2 % larger a frame) to 2^-16, for the same reason.
inline double to_zoom_step(double zoom) { return std::round(zoom * 65536) / 65536; }

struct DominantMotionOptions {
  int max_pairs = 16;
  double max_residual_share = 0.5;
  double min_agreeing_share = 0.75;
  double min_shift = 1.0;  // pixels a frame
  int zoom_blocks = 4;             // blocks a side
  int min_zoom_blocks = 8;         // with texture, for a fit
  double min_block_texture = 4e-3;  // mean neighbour difference (1 = the range)
  double max_total_zoom = 16;
};

struct DominantMotion {
  double dx = 0, dy = 0;  // pixels a frame (0, 0 when none was found)
  double zoom = 0;        // relative, a frame, about the frame's centre (0 when none was found)
  bool found = false;
  double median_dx = 0, median_dy = 0;  // the pairs' median, kept or not
  int pairs = 0;                        // frame pairs matched
  int agreeing = 0;                     // of them explained by the median
  double median_zoom = 0;               // the zoom model's median (when no translation was found)
  int zoom_agreeing = 0;                // pairs explained by it
  // Not found, but the pairs agree on a translation (or, slow_zoom, a zoom)
  // that moves the frame by min_shift pixels or less a frame; still frames
  // too. The lattice's mesh serves it; upscale_sequence then narrows the
  // graduated optimization (sequence_upscale.hpp).
  bool slow = false;
  bool slow_zoom = false;
};

DominantMotion dominant_motion(int frames, const std::function<Image(int)>& frame,
                               const DominantMotionOptions& options = {});

}  // namespace ddt
