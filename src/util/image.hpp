#pragma once
// ddt::Image — the library's in-memory raster: float samples, interleaved
// channels, rows top to bottom.
//
// Pixel convention (used everywhere in ddtscale): sample (x, y) sits at the
// pixel centre (x + 0.5, y + 0.5) in continuous image coordinates, so an
// image of width W covers [0, W) and its samples span [0.5, W - 0.5].
// An output pixel X of an image enlarged by sx samples the input at
// (X + 0.5) / sx.

#include <cstddef>
#include <vector>

namespace ddt {

struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;  // width * height * channels, interleaved

  Image() = default;
  Image(int w, int h, int c, float fill = 0.0f)
      : width(w), height(h), channels(c), pixels(static_cast<std::size_t>(w) * h * c, fill) {}

  std::size_t pixel_count() const { return static_cast<std::size_t>(width) * height; }
  bool empty() const { return pixels.empty(); }

  std::size_t index(int x, int y, int c = 0) const {
    return (static_cast<std::size_t>(y) * width + x) * channels + c;
  }
  float& at(int x, int y, int c = 0) { return pixels[index(x, y, c)]; }
  float at(int x, int y, int c = 0) const { return pixels[index(x, y, c)]; }
};

}  // namespace ddt
