#pragma once
// ddt::peer_resize — the upscalers of other libraries a user could call
// instead of ddtscale, run in `ddtscale eval` on the same inputs (issue 15):
//
//   "opencv-lanczos4"  OpenCV cv::resize, INTER_LANCZOS4 (8x8 taps)
//   "opencv-cubic"     OpenCV cv::resize, INTER_CUBIC (Keys a = -0.75, 4x4)
//   "vips-nohalo"      libvips vips_affine with the "nohalo" interpolator
//                      (Nohalo subdivision + LBB: no overshoot, sharp edges)
//
// Sampling convention, the same for all three and the one of image.hpp:
// output pixel X samples the input at (X + 0.5) / s - 0.5 in pixel-index
// units, s = out_width / src.width (per axis). cv::resize uses it natively.
// vips_affine maps output X to input X / s by default (corners aligned at
// index 0); its idx = idy = 0.5, odx = ody = -0.5 displacements turn that
// into the centre convention, and the border is extended by copying the edge
// pixels (VIPS_EXTEND_COPY, OpenCV's resize replicates too). vips_resize is
// not used: it offers no nohalo kernel when enlarging (it upsizes with its
// own bicubic interpolator).
//
// Both libraries run on the float samples as given (no 8-bit conversion);
// the results are not clamped (Lanczos-4 and cubic overshoot at edges).
//
// Inputs:
//   src            width x height x channels, any channel count >= 1
//   out_w, out_h   >= 1 (any enlargement or reduction; the peers are meant
//                  for enlargement, vips-nohalo does not antialias)
//   method         one of peer_methods()
// Outputs:
//   returns        out_w x out_h x src.channels
// Errors: throws ddt::Error with a one-line message for an unknown method
// (listing the valid names), an empty src, a non-positive size or a failure
// inside OpenCV or libvips. Safe to call from several threads.

#include "util/image.hpp"

#include <string>
#include <vector>

namespace ddt {

Image peer_resize(const Image& src, int out_w, int out_h, const std::string& method);

// The method names peer_resize accepts, in the order of the table above.
std::vector<std::string> peer_methods();

}  // namespace ddt
