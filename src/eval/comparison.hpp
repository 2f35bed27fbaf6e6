#pragma once
// ddt::side_by_side — two equally sized images in one, left | right, with a
// thin vertical separator, as in figure 1 of the paper (bicubic beside DDT).
//
// Inputs:
//   left, right      same width, height and channel count
//   separator_px     separator width in pixels (>= 0)
//   separator_value  its value in every colour channel (alpha, if
//                    alpha_channel >= 0, is set to 1)
// Output: (2 * width + separator_px) x height x channels; columns
//   [0, width) are `left`, [width + separator_px, 2 width + separator_px)
//   are `right`, bit for bit.
// Errors: ddt::Error when the sizes differ.

#include "util/image.hpp"

namespace ddt {

Image side_by_side(const Image& left, const Image& right, int separator_px = 2, float separator_value = 0.0f,
                   int alpha_channel = -1);

}  // namespace ddt
