#include "eval/comparison.hpp"

#include "util/error.hpp"

#include <algorithm>

namespace ddt {

Image side_by_side(const Image& left, const Image& right, int separator_px, float separator_value,
                   int alpha_channel) {
  if (left.width != right.width || left.height != right.height || left.channels != right.channels)
    throw Error("side_by_side: the two images differ in size or channels");
  separator_px = std::max(0, separator_px);
  const int w = left.width, C = left.channels;
  Image out(2 * w + separator_px, left.height, C, separator_value);
  for (int y = 0; y < left.height; ++y) {
    std::copy_n(&left.pixels[left.index(0, y)], static_cast<std::size_t>(w) * C, &out.pixels[out.index(0, y)]);
    std::copy_n(&right.pixels[right.index(0, y)], static_cast<std::size_t>(w) * C,
                &out.pixels[out.index(w + separator_px, y)]);
    if (alpha_channel >= 0 && alpha_channel < C)
      for (int x = w; x < w + separator_px; ++x) out.at(x, y, alpha_channel) = 1.0f;
  }
  return out;
}

}  // namespace ddt
