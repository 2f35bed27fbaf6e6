#pragma once
// ddt::matlab_imresize_bicubic — MATLAB's imresize(A, [h w], 'bicubic'),
// reimplemented so the super-resolution protocol (LR generation and the
// reference "bicubic" row of the published tables) can be reproduced
// without MATLAB.
//
// What MATLAB does, and so what this does:
//   - Keys cubic kernel with a = -0.5 (support [-2, 2]).
//   - Per dimension, scale = out_length / in_length. When scale < 1 the
//     kernel is stretched to h(x) = scale * cubic(scale * x), width
//     4 / scale (antialiasing); when scale >= 1 it is used as is.
//   - Output sample x (1-based) maps to input coordinate
//         u = x / scale + 0.5 * (1 - 1 / scale)      (1-based),
//     which is the pixel-centre convention of ddt::Image (image.hpp)
//     written in MATLAB's 1-based indices. Taps are the integers
//     floor(u - width / 2) + [0, ceil(width) + 2); their weights are
//     normalized to sum to 1 for every output sample.
//   - Taps outside the image are mirrored with the edge sample repeated
//     (MATLAB's aux = [1:n, n:-1:1] 'symmetric' padding).
//   - Separable: one 1-D pass per dimension, the dimension with the smaller
//     scale first; on a tie MATLAB's stable sort puts dimension 1 (rows,
//     i.e. the height) first, so equal scales resize the height, then the
//     width.
//   - Arithmetic in double, as MATLAB does for double input. (MATLAB on
//     uint8 input also rounds to uint8 between the two passes; callers of
//     this function pass floats, so that variant is not reproduced.)
//
// Inputs:
//   src         width x height x channels, any channel count, any values
//   out_width   >= 1
//   out_height  >= 1
// Outputs:
//   returns     out_width x out_height x src.channels, no clamping
//               (the cubic kernel overshoots near edges, as in MATLAB)
// Errors: throws ddt::Error on an empty src or a non-positive size.
// Complexity: O(out pixels * channels * taps), taps = ceil(4 / min(scale, 1)) + 2.

#include "util/image.hpp"

#include <vector>

namespace ddt {

// The taps of one 1-D pass from in_length to out_length samples: output
// sample o reads input samples index[o * taps + k] (0-based, mirrored at the
// borders) with weight[o * taps + k]; each output's weights sum to 1.
struct MatlabTaps {
  int taps = 0;
  std::vector<int> index;
  std::vector<double> weight;
};
MatlabTaps matlab_taps(int in_length, int out_length);

Image matlab_imresize_bicubic(const Image& src, int out_width, int out_height);

// Rounds every sample to the nearest of the 256 levels of an 8-bit image:
// v -> round(clamp(v, 0, 1) * 255) / 255, halves away from zero, like
// MATLAB's conversion of a double result to uint8 (im2uint8).
//
// Inputs:  src  any image, values nominally in 0..1
// Outputs: returns an image of the same shape
Image round_to_8bit(const Image& src);

}  // namespace ddt
