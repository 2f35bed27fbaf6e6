// The public ImageBuf forms of upscale (ddtscale/ddtscale.hpp): validate and
// allocate, run the Image pipeline (upscale.hpp) in the caller's thread
// budget, copy the window out.

#include "ddtscale/ddtscale.hpp"

#include "io/image_io.hpp"
#include "pipeline/output_size.hpp"
#include "pipeline/upscale.hpp"

#include <tbb/task_arena.h>

#include <algorithm>
#include <string>

namespace ddt {
namespace {

std::string window_text(const OIIO::ROI& roi) {
  return "[" + std::to_string(roi.xbegin) + ", " + std::to_string(roi.xend) + ") x [" + std::to_string(roi.ybegin) +
         ", " + std::to_string(roi.yend) + ")";
}

// The destination window: all of the output unless given; throws unless it
// is a non-empty part of the out_w x out_h x channels output.
OIIO::ROI destination_window(OIIO::ROI roi, int out_w, int out_h, int channels) {
  if (!roi.defined()) return OIIO::ROI(0, out_w, 0, out_h, 0, 1, 0, channels);
  roi.chend = std::min(roi.chend, channels);
  if (roi.xbegin < 0 || roi.ybegin < 0 || roi.xend > out_w || roi.yend > out_h || roi.xbegin >= roi.xend ||
      roi.ybegin >= roi.yend || roi.zbegin != 0 || roi.zend != 1 || roi.chbegin < 0 || roi.chbegin >= roi.chend)
    throw Error("the window " + window_text(roi) + " is not a non-empty part of the " + std::to_string(out_w) + "x" +
                std::to_string(out_h) + " output (channels 0.." + std::to_string(channels - 1) + ")");
  return roi;
}

void run(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const UpscaleOptions& options, OIIO::ROI roi,
         UpscaleStats* stats) {
  // spec() reads a file-backed image's header; a missing file is an error on src.
  const OIIO::ImageSpec& in_spec = src.spec();
  if (src.has_error()) throw Error(src.geterror());
  if (in_spec.width < 1 || in_spec.height < 1 || in_spec.nchannels < 1) throw Error("the input image is empty");
  SizeRequest request;
  if (options.scale != 0) request.scale = options.scale;
  if (options.width != 0) request.width = options.width;
  if (options.height != 0) request.height = options.height;
  request.max_pixels = options.max_pixels;
  int out_w = 0, out_h = 0;
  output_size(request, in_spec.width, in_spec.height, out_w, out_h);
  roi = destination_window(roi, out_w, out_h, in_spec.nchannels);
  if (dst.initialized()) {
    const OIIO::ROI have = dst.roi();
    if (roi.xbegin < have.xbegin || roi.xend > have.xend || roi.ybegin < have.ybegin || roi.yend > have.yend ||
        roi.chend - roi.chbegin > have.chend)
      throw Error("dst does not hold the window " + window_text(roi) + " and its " +
                  std::to_string(roi.chend - roi.chbegin) + " channels");
  }

  UpscaleOptions opts = options;
  if (opts.alpha_channel < 0) opts.alpha_channel = in_spec.alpha_channel;
  const Image in = image_from_buf(src);
  if (src.has_error()) throw Error(src.geterror());
  const Image out = upscale(in, out_w, out_h, opts, stats);

  // The window's pixels, channels [chbegin, chend).
  const int window_channels = roi.chend - roi.chbegin;
  Image window(roi.width(), roi.height(), window_channels);
  for (int y = 0; y < window.height; ++y)
    for (int x = 0; x < window.width; ++x)
      for (int c = 0; c < window_channels; ++c)
        window.at(x, y, c) = out.at(roi.xbegin + x, roi.ybegin + y, roi.chbegin + c);
  if (!dst.initialized()) {
    OIIO::ImageSpec spec(window.width, window.height, window_channels, OIIO::TypeDesc::FLOAT);
    spec.x = roi.xbegin;
    spec.y = roi.ybegin;
    spec.full_x = spec.full_y = 0;
    spec.full_width = out_w;
    spec.full_height = out_h;
    const int alpha = opts.alpha_channel - roi.chbegin;
    if (alpha >= 0 && alpha < window_channels) spec.alpha_channel = alpha;
    dst.reset(spec);
  }
  const OIIO::ROI target(roi.xbegin, roi.xend, roi.ybegin, roi.yend, 0, 1, 0, window_channels);
  if (!dst.set_pixels(target, OIIO::TypeDesc::FLOAT, window.pixels.data()))
    throw Error("could not write the window into dst: " + dst.geterror());
}

}  // namespace

bool upscale(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const UpscaleOptions& options, OIIO::ROI roi,
             int nthreads, UpscaleStats* stats) {
  try {
    if (nthreads < 0) throw Error("nthreads must be >= 0 (0: the default)");
    if (nthreads == 0) {
      run(dst, src, options, roi, stats);
    } else {
      tbb::task_arena arena(nthreads);
      arena.execute([&] { run(dst, src, options, roi, stats); });
    }
    return true;
  } catch (const std::bad_alloc&) {
    dst.errorfmt("out of memory (try a smaller output)");
  } catch (const std::exception& e) {
    dst.errorfmt("{}", e.what());
  }
  return false;
}

OIIO::ImageBuf upscale(const OIIO::ImageBuf& src, const UpscaleOptions& options, OIIO::ROI roi, int nthreads,
                       UpscaleStats* stats) {
  OIIO::ImageBuf dst;
  upscale(dst, src, options, roi, nthreads, stats);
  return dst;
}

}  // namespace ddt
