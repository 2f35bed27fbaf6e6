#pragma once
// Measures of an upscaler's edges against a known truth (issue 15): how
// wide, how straight and how far beyond its levels a reconstructed straight
// step edge is, and how far an output leaves the range of the true scene
// (the truth-based halo). Pure functions: images and known geometry in,
// numbers out.
//
// Coordinates are the continuous pixel coordinates of the image measured
// (image.hpp): pixel (x, y) covers [x, x + 1) x [y, y + 1), its sample sits
// at (x + 0.5, y + 0.5). Results are in *input* pixels: an image enlarged by
// s has s output pixels per input pixel, so distances are divided by s.

#include "util/image.hpp"

namespace ddt {

// A straight step edge: level `low` where n . (p - point) < 0, `high` where
// it is > 0 (high > low; flip the normal for a dark-on-the-right edge).
struct StepEdge {
  double x = 0, y = 0;       // a point on the edge, in the measured image's pixel coordinates
  double nx = 1, ny = 0;     // unit normal towards the `high` side
  double low = 0, high = 1;  // the two levels
};

struct EdgeSharpnessOptions {
  double half_length = 3.0;  // profile reach on each side of the true line, input pixels
  double margin = 3.0;       // input pixels every profile keeps clear of the image border
  double spacing = 0.25;     // output pixels between neighbouring profiles along the edge
  double step = 0.25;        // output pixels between samples along a profile
  int channel = 0;           // the channel measured
};

struct EdgeSharpness {
  // Mean over profiles of the distance between the 10 % and 90 % crossings
  // (levels low + 0.1 (high - low), low + 0.9 (high - low)), input pixels.
  // The image's own grid bounds it from below: an ideal box-filtered edge,
  // sampled at the pixel centres and interpolated between them, measures
  // 0.8 to 1.6 of the measured image's pixels (1.58 at 0 degrees with the
  // edge 0.4 into a pixel), i.e. 0.08-0.16 input pixels at scale 10.
  double rise_width = 0;
  // RMS distance of the 50 % crossing from the true line (the bias
  // included), input pixels: 0 for a straight edge in the right place.
  double wobble = 0;
  // Mean signed distance of the 50 % crossing from the true line (positive:
  // displaced towards `high`), input pixels; wobble^2 - offset^2 is the
  // variance of the contour about its own mean.
  double offset = 0;
  // Largest excursion beyond [low, high] of any pixel whose centre lies in
  // the measured band (within half_length of the line, between the first
  // and last profile), percent of high - low; 0 when none.
  double overshoot = 0;
  int profiles = 0;  // profiles on which all three crossings were found
};

// Samples the image along many profiles perpendicular to the true edge:
// one every `spacing` output pixels along the part of the line whose
// profiles (reaching half_length input pixels on each side) stay `margin`
// input pixels inside the image; along each, samples every `step` output
// pixels by bilinear interpolation of the pixel samples. On each profile the
// upward 50 % crossing nearest the true line is located by linear
// interpolation between samples, then the 10 % crossing is the nearest one
// towards the low side and the 90 % crossing the nearest one towards the
// high side (so ringing further out does not count as the edge).
// Inputs:
//   img    width x height x channels, channel options.channel measured
//   edge   the true edge, unit normal, high > low
//   scale  output pixels per input pixel (> 0); 1 measures in img's own pixels
// Outputs: the measures above; when no profile fits or none has all three
//   crossings, profiles = 0 and rise_width, wobble and offset are NaN.
// Errors: throws ddt::Error for an empty image, a bad channel, a normal
//   that is not unit length, high <= low, or non-positive scale, spacing or step.
// Complexity: O(profiles * half_length * scale / step + band pixels).
EdgeSharpness measure_edge_sharpness(const Image& img, const StepEdge& edge, double scale,
                                     const EdgeSharpnessOptions& options = {});

struct TruthHaloOptions {
  // What the excursion is divided by, per pixel P and channel c:
  //   step > 0           that number everywhere (e.g. a scene's known step);
  //   step 0, not local  the truth's range in channel c, max - min over the
  //                      whole image: the scene's step (the default);
  //   step 0, local      max - min of the truth within step_reach input
  //                      pixels of P (square window). Beware: where that
  //                      window barely reaches a step, the divisor is a
  //                      sliver of it and faint ringing scores high.
  // A divisor below min_step (flat truth: nothing to ring against) skips
  // the pixel (local) or the channel.
  double step = 0;
  bool local = false;
  double step_reach = 3.0;  // input pixels; local mode only
  double min_step = 1e-3;
  int shave = 0;            // output pixels on every border left out
};

// The truth-based halo: the largest fraction of the step by which the
// output leaves [min, max] of the truth over the output pixels within one
// input pixel of it (the square window |dX|, |dY| <= floor(scale) output
// pixels, clipped to the image):
//   max over pixels P and channels c of
//     max(out(P) - max_W truth, min_W truth - out(P), 0) / step(P, c).
// It counts overshoot, and also blur that spreads a step over more than one
// input pixel on either side of the true edge (the output has not reached
// the level where the truth has been flat for a whole input pixel).
// A nearest-neighbour enlargement of a box-filtered input scores 0 (each
// input pixel is an average of the truth over its footprint, which lies in
// the window of each of its output pixels); bicubic and Lanczos ring beside
// every step edge and score several percent.
// Inputs:
//   output, truth  the same width x height x channels (truth: the true
//                  scene rendered at the output's resolution)
//   scale          output pixels per input pixel, >= 1
// Outputs: the fraction (0.01 = 1 %), >= 0.
// Errors: throws ddt::Error for mismatched or empty images, scale < 1, a
//   negative step, or a shave that leaves no pixel.
// Complexity: O(width * height * channels) (sliding-window min and max).
double truth_halo(const Image& output, const Image& truth, double scale, const TruthHaloOptions& options = {});

}  // namespace ddt
