#pragma once
// ddt::slow_texture_samples — the samples of an image sequence where fine
// two-dimensional texture moves by at most a pixel to the next frame, so
// that the flips leave them paired along time (docs/sequences.md, "Slow
// motion on photographs").
//
// Why: the mesh pairs samples a whole number of pixels apart. A moving
// edge is one-dimensional, so the mesh can follow it whatever the motion
// by pairing samples along the edge. Texture is two-dimensional: only a
// whole-pixel shift pairs it right, and where it moves less than that the
// edge along time (frame blending) is the best pairing the lattice has.
// The variance cost does not see this: on texture it prefers flips that
// join neighbours across time, and the frames between blur.
//
// A sample (x, y, t), t < T - 1, is flagged when, in both frames t and
// t + 1:
//   - the structure tensor (the outer products of the central-difference
//     gradients, summed over the channels and a 3x3 window) has a trace
//     above min_structure (not flat), and a coherence
//     ((l1 - l2) / (l1 + l2))^2 of at most max_coherence (not an edge);
//   and the whole-pixel shift (ex, ey), |ex|, |ey| <= search, whose
//   (2 patch + 1)^2 patch of frame t + 1 differs least from the patch of
//   frame t at (x, y) (sum of absolute differences over the channels;
//   ties to the smaller shift) has max(|ex|, |ey|) <= max_shift, and
//   is a match: its difference at most match_share of the mean over the
//   shifts searched (else the motion is beyond the search, or the texture
//   repeats, and nothing is known).
//
// values: channels fastest, then x, y, t (width x height x frames).
// Returns a flag per sample; the last frame's are 0.
// Errors: ddt::Error on bad sizes.

#include <vector>

namespace ddt {

struct SlowTextureOptions {
  double max_coherence = 0.75;
  double min_structure = 1e-3;
  int search = 3;     // pixels, each way
  int patch = 2;      // patch radius in pixels (5x5)
  int max_shift = 1;  // pixels
  double match_share = 0.8;
};

std::vector<char> slow_texture_samples(const std::vector<float>& values, int width, int height, int frames,
                                       int channels, const SlowTextureOptions& options = {});

}  // namespace ddt
