#pragma once
// ddt::classic_resize — the textbook resamplers, through OpenImageIO, as
// baselines for the evaluation. No kernels are written here.
//
//   "nearest"   ImageBufAlgo::resample(interpolate = false): each output
//               pixel copies the input pixel whose square holds its centre
//               (pure pixel replication for integer enlargement)
//   "bilinear"  ImageBufAlgo::resize with the "triangle" filter
//   "bicubic"   ImageBufAlgo::resize with "catmull-rom" (Keys, a = -0.5)
//   "lanczos"   ImageBufAlgo::resize with "lanczos3"
//
// The filters get OIIO's default width (filterwidth 0). OIIO 2.4 expresses
// a width in output pixels and, by default, multiplies the filter's natural
// width by the enlargement on each axis, so each filter keeps its natural
// support in input pixels: true bilinear (and true Catmull-Rom, Lanczos-3)
// interpolation when upscaling, antialiased when downscaling. An explicit
// width would be wrong on one axis whenever the two enlargements differ.
// Samples follow the pixel-centre convention of image.hpp. Near the border
// OIIO's treatment differs from MATLAB's mirror, so "bicubic" here is not
// matlab_imresize_bicubic (matlab_resize.hpp) there.
//
// Inputs:
//   src            width x height x channels, any channel count
//   out_w, out_h   >= 1
//   method         one of classic_methods()
// Outputs:
//   returns        out_w x out_h x src.channels, not clamped (Catmull-Rom and
//                  Lanczos overshoot at edges)
// Errors: throws ddt::Error for an unknown method (the message lists the
// valid names), an empty src, a non-positive size or an OIIO failure.

#include "util/image.hpp"

#include <string>
#include <vector>

namespace ddt {

Image classic_resize(const Image& src, int out_w, int out_h, const std::string& method);

// The method names classic_resize accepts, in the order of the table above.
std::vector<std::string> classic_methods();

}  // namespace ddt
