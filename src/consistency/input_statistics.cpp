#include "consistency/input_statistics.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>

namespace ddt {

InputStatistics input_statistics(const Image& image) {
  if (image.empty() || image.channels < 1) throw Error("input statistics of an empty image");
  const int C = image.channels;
  InputStatistics s;
  s.min.assign(image.pixels.begin(), image.pixels.begin() + C);
  s.max = s.min;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const int c = static_cast<int>(i % C);
    s.min[c] = std::min(s.min[c], image.pixels[i]);
    s.max[c] = std::max(s.max[c], image.pixels[i]);
  }
  // A sample on the 8-bit grid is on the 16-bit one too (1/255 = 257/65535).
  for (double levels : {255.0, 65535.0}) {
    bool on_grid = true;
    for (std::size_t i = 0; i < image.pixels.size() && on_grid; ++i) {
      const double code = image.pixels[i] * levels;
      on_grid = std::abs(code - std::round(code)) < 1e-3;
    }
    if (on_grid) {
      s.quantum = 1 / levels;
      break;
    }
  }
  return s;
}

InputStatistics merge(const InputStatistics& a, const InputStatistics& b) {
  if (a.min.size() != b.min.size()) throw Error("input statistics of images with different channels");
  InputStatistics s = a;
  for (std::size_t c = 0; c < a.min.size(); ++c) {
    s.min[c] = std::min(a.min[c], b.min[c]);
    s.max[c] = std::max(a.max[c], b.max[c]);
  }
  s.quantum = a.quantum == 0 || b.quantum == 0 ? 0 : std::min(a.quantum, b.quantum);
  return s;
}

InputStatistics input_statistics(const RowSource& source, Progress* progress) {
  constexpr int chunk = 256;
  if (source.width <= 0 || source.height <= 0) throw Error("input statistics of an empty image");
  if (progress) progress->begin("statistics", source.height);
  InputStatistics all;
  Image rows(source.width, std::min(chunk, source.height), source.channels);
  for (int first = 0; first < source.height; first += chunk) {
    const int end = std::min(source.height, first + chunk);
    rows.height = end - first;
    rows.pixels.resize(static_cast<std::size_t>(source.width) * source.channels * rows.height);
    source.read(first, end, rows.pixels.data());
    const InputStatistics part = input_statistics(rows);
    all = first == 0 ? part : merge(all, part);
    if (progress) progress->set(end);
  }
  return all;
}

}  // namespace ddt
