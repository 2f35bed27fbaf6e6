#include "eval/classic_resize.hpp"

#include "util/error.hpp"
#include "util/text.hpp"
#include "io/image_io.hpp"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

namespace ddt {

Image classic_resize(const Image& src, int out_w, int out_h, const std::string& method) {
  std::string filter;
  if (method == "bilinear") filter = "triangle";
  else if (method == "bicubic") filter = "catmull-rom";
  else if (method == "lanczos") filter = "lanczos3";
  else if (method != "nearest") {
    throw Error("unknown resize method '" + method + "' (valid: " + joined(classic_methods()) + ")");
  }
  if (src.empty() || src.width <= 0 || src.height <= 0 || src.channels <= 0)
    throw Error("classic_resize: the source image is empty");
  if (out_w < 1 || out_h < 1)
    throw Error("classic_resize: output size " + std::to_string(out_w) + "x" + std::to_string(out_h) +
                " is not positive");

  const OIIO::ImageBuf in = buf_from_image(src);
  OIIO::ImageBuf out(OIIO::ImageSpec(out_w, out_h, src.channels, OIIO::TypeDesc::FLOAT));
  // filterwidth 0: OIIO scales the filter's natural width by the enlargement (see header).
  const bool ok = filter.empty() ? OIIO::ImageBufAlgo::resample(out, in, /*interpolate=*/false)
                                 : OIIO::ImageBufAlgo::resize(out, in, filter, /*filterwidth=*/0.0f);
  if (!ok) {
    std::string why = out.geterror();
    why = why.substr(0, why.find('\n'));  // ddt::Error messages are one line
    throw Error("classic_resize (" + method + "): " + why);
  }
  return image_from_buf(out);
}

}  // namespace ddt
