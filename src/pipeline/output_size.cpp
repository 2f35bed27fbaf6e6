#include "pipeline/output_size.hpp"

#include "util/error.hpp"
#include "util/size_limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace ddt {

void output_size(const SizeRequest& request, int in_w, int in_h, int& out_w, int& out_h) {
  const bool scale_given = request.scale.has_value();
  const bool width_given = request.width.has_value(), height_given = request.height.has_value();
  if (scale_given && (width_given || height_given))
    throw Error("give either --scale or --width/--height, not both");
  if (scale_given) {
    const double scale = *request.scale;
    if (!(scale > 0) || !std::isfinite(scale)) throw Error("--scale must be a positive number");
    const double w = std::round(in_w * scale), h = std::round(in_h * scale);
    if (w > 2e9 || h > 2e9) throw Error("--scale gives an output larger than --max-pixels");
    out_w = static_cast<int>(std::max(1.0, w));
    out_h = static_cast<int>(std::max(1.0, h));
  } else if (width_given || height_given) {
    const int width = request.width.value_or(0), height = request.height.value_or(0);
    if ((width_given && width <= 0) || (height_given && height <= 0))
      throw Error("--width and --height must be positive");
    out_w = width > 0 ? width : static_cast<int>(std::max(1.0, std::round(double(in_w) * height / in_h)));
    out_h = height > 0 ? height : static_cast<int>(std::max(1.0, std::round(double(in_h) * width / in_w)));
  } else {
    throw Error("give the magnification: --scale S, or --width W and/or --height H");
  }
  const long long pixels = checked_product({out_w, out_h});
  // What a user enlarging a large scan needs to know: how big, and the
  // value that allows it (a streamed output under --model point holds a
  // few bands of it, not the whole).
  char size[96];
  std::snprintf(size, sizeof size, "%dx%d (%.0f Mpixels)", out_w, out_h, pixels / 1e6);
  check_size_limit("output", size, pixels, request.max_pixels, "--max-pixels");
}

}  // namespace ddt
