#pragma once
// ddtscale — enlarge images by data-dependent triangulation (DDT): the
// library's public interface, in the shape of OpenImageIO's ImageBufAlgo.
//
//   ddt::UpscaleOptions options;
//   options.scale = 4;
//   OIIO::ImageBuf big = ddt::upscale(src, options);
//   if (big.has_error()) ... big.geterror() ...
//
// Rules shared by both forms (as ImageBufAlgo's "common principles"):
// - Output size: from the options (scale, or width and/or height; see
//   UpscaleOptions), at most options.max_pixels pixels.
// - roi: the destination window, in output pixels (x in [xbegin, xend),
//   y in [ybegin, yend), channels [chbegin, chend) of the source's); the
//   default is all of the output. The window's pixels are those of the
//   whole output (the mesh is the whole image's; the window is cut from
//   the whole enlargement, so its cost is that of the whole output).
// - dst: uninitialized, it is allocated to the window (float pixels, its
//   data window at the ROI's origin, its full size the whole output's);
//   initialized, the window is written into it, which must hold the
//   ROI's pixels and channels.
// - nthreads: 0 the global default (all cores, or what the caller's TBB
//   arena or global_control allows), n > 0 at most n threads. The output
//   never depends on it.
// - Errors: bad options or images make the bool form return false with the
//   message on dst (dst.geterror()), the by-value form return an image
//   whose has_error() is true. Nothing throws.
// - Pixel convention: sample (x, y) sits at (x + 0.5, y + 0.5); output pixel
//   X samples the surface at (X + 0.5) / sx with sx = out_width / in_width.
//   Outside the samples' convex hull (the half-pixel rim) the value is that
//   of the nearest hull point.
// - Alpha (options.alpha_channel, or the spec's alpha channel when -1) is
//   interpolated on the same mesh and never drives the flips.

#include "ddtscale/error.hpp"
#include "ddtscale/options.hpp"
#include "ddtscale/stats.hpp"

#include <OpenImageIO/imagebuf.h>

namespace ddt {

// Enlarges src into dst's window roi. stats: if given, filled on success.
bool upscale(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const UpscaleOptions& options, OIIO::ROI roi = {},
             int nthreads = 0, UpscaleStats* stats = nullptr);

// The same, returning the window as a new image (errors on it).
OIIO::ImageBuf upscale(const OIIO::ImageBuf& src, const UpscaleOptions& options, OIIO::ROI roi = {}, int nthreads = 0,
                       UpscaleStats* stats = nullptr);

}  // namespace ddt
