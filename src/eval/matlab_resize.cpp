#include "eval/matlab_resize.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace ddt {
namespace {

// Keys cubic convolution kernel, a = -0.5 (MATLAB's imresize 'cubic').
double cubic(double x) {
  const double ax = std::abs(x);
  const double ax2 = ax * ax;
  const double ax3 = ax2 * ax;
  if (ax <= 1) return 1.5 * ax3 - 2.5 * ax2 + 1;
  if (ax <= 2) return -0.5 * ax3 + 2.5 * ax2 - 4 * ax + 2;
  return 0;
}

}  // namespace

// MATLAB's contributions(): same formulas, same order of operations.
MatlabTaps matlab_taps(int in_length, int out_length) {
  const double scale = static_cast<double>(out_length) / in_length;
  const bool antialias = scale < 1;
  const double kernel_width = antialias ? 4.0 / scale : 4.0;
  MatlabTaps c;
  c.taps = static_cast<int>(std::ceil(kernel_width)) + 2;
  c.index.resize(static_cast<std::size_t>(out_length) * c.taps);
  c.weight.resize(c.index.size());
  const long long period = 2LL * in_length;  // length of aux = [1:n, n:-1:1]
  for (int o = 0; o < out_length; ++o) {
    const double x = o + 1;  // 1-based output coordinate
    const double u = x / scale + 0.5 * (1 - 1 / scale);
    const double left = std::floor(u - kernel_width / 2);
    double sum = 0;
    for (int k = 0; k < c.taps; ++k) {
      const double ind = left + k;  // 1-based input index, may lie outside
      const double w = antialias ? scale * cubic(scale * (u - ind)) : cubic(u - ind);
      // MATLAB: aux(mod(ind - 1, 2n) + 1), a mirror that repeats the edge sample.
      long long m = (static_cast<long long>(ind) - 1) % period;
      if (m < 0) m += period;
      const long long zero_based = m < in_length ? m : period - 1 - m;
      const std::size_t slot = static_cast<std::size_t>(o) * c.taps + k;
      c.index[slot] = static_cast<int>(zero_based);
      c.weight[slot] = w;
      sum += w;
    }
    for (int k = 0; k < c.taps; ++k) c.weight[static_cast<std::size_t>(o) * c.taps + k] /= sum;
  }
  return c;
}

namespace {

// A double-precision raster with the layout of ddt::Image.
struct Plane {
  int width = 0, height = 0, channels = 0;
  std::vector<double> v;
  std::size_t at(int x, int y, int ch) const {
    return (static_cast<std::size_t>(y) * width + x) * channels + ch;
  }
};

// One separable pass: resizes the width (along_x) or the height to out_length.
Plane resize_along(const Plane& in, bool along_x, int out_length) {
  const int in_length = along_x ? in.width : in.height;
  const MatlabTaps c = matlab_taps(in_length, out_length);
  Plane out;
  out.width = along_x ? out_length : in.width;
  out.height = along_x ? in.height : out_length;
  out.channels = in.channels;
  out.v.assign(static_cast<std::size_t>(out.width) * out.height * out.channels, 0.0);
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      const int o = along_x ? x : y;
      for (int ch = 0; ch < out.channels; ++ch) {
        double acc = 0;
        for (int k = 0; k < c.taps; ++k) {
          const std::size_t slot = static_cast<std::size_t>(o) * c.taps + k;
          const int i = c.index[slot];
          acc += c.weight[slot] * (along_x ? in.v[in.at(i, y, ch)] : in.v[in.at(x, i, ch)]);
        }
        out.v[out.at(x, y, ch)] = acc;
      }
    }
  }
  return out;
}

}  // namespace

Image matlab_imresize_bicubic(const Image& src, int out_width, int out_height) {
  if (src.empty() || src.width <= 0 || src.height <= 0 || src.channels <= 0)
    throw Error("matlab_imresize_bicubic: the source image is empty");
  if (out_width < 1 || out_height < 1)
    throw Error("matlab_imresize_bicubic: output size " + std::to_string(out_width) + "x" +
                std::to_string(out_height) + " is not positive");

  Plane p;
  p.width = src.width;
  p.height = src.height;
  p.channels = src.channels;
  p.v.assign(src.pixels.begin(), src.pixels.end());

  const double scale_h = static_cast<double>(out_height) / src.height;
  const double scale_w = static_cast<double>(out_width) / src.width;
  // MATLAB: [~, order] = sort(scale) — smaller scale first, ties keep dim 1 (height) first.
  if (scale_h <= scale_w) {
    p = resize_along(p, false, out_height);
    p = resize_along(p, true, out_width);
  } else {
    p = resize_along(p, true, out_width);
    p = resize_along(p, false, out_height);
  }

  Image out(out_width, out_height, src.channels);
  std::transform(p.v.begin(), p.v.end(), out.pixels.begin(),
                 [](double d) { return static_cast<float>(d); });
  return out;
}

Image round_to_8bit(const Image& src) {
  Image out = src;
  for (float& v : out.pixels) {
    const double clamped = std::clamp(static_cast<double>(v), 0.0, 1.0);
    v = static_cast<float>(std::round(clamped * 255.0) / 255.0);
  }
  return out;
}

}  // namespace ddt
