#include "consistency/input_statistics.hpp"

#include "util/error.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace ddt {

namespace {

// The per channel range of samples [first, end) (whole pixels), and
// whether every one of them is on the 8-bit code grid.
struct Part {
  std::vector<float> min, max;
  bool on_8bit = true;
};

// A code c read as the float nearest c / levels is off by up to half a
// float's spacing, 2^-24 of it: up to 0.002 of a code at 16 bits, more
// than the thousandth allowed otherwise (then three in four 16-bit codes
// failed, and 16-bit inputs counted as float ones).
bool on_code_grid(float value, double levels) {
  const double code = value * levels;
  return std::abs(code - std::round(code)) < std::max(1e-3, 4 * std::abs(code) * 0x1p-24);
}

Part part_of(const std::vector<float>& pixels, int C, std::size_t first, std::size_t end) {
  Part part;
  part.min.assign(pixels.begin() + static_cast<std::ptrdiff_t>(first),
                  pixels.begin() + static_cast<std::ptrdiff_t>(first) + C);
  part.max = part.min;
  for (std::size_t i = first; i < end; ++i) {
    const int c = static_cast<int>((i - first) % C);
    part.min[c] = std::min(part.min[c], pixels[i]);
    part.max[c] = std::max(part.max[c], pixels[i]);
  }
  for (std::size_t i = first; i < end && part.on_8bit; ++i) part.on_8bit = on_code_grid(pixels[i], 255.0);
  return part;
}

}  // namespace

InputStatistics input_statistics(const Image& image) {
  if (image.empty() || image.channels < 1) throw Error("input statistics of an empty image");
  const int C = image.channels;
  // Blocks of whole pixels, each on a thread; min, max and "and" merge in
  // any order to the same result.
  constexpr std::size_t block_pixels = 1 << 16;
  const std::size_t pixels = image.pixels.size() / C, blocks = (pixels + block_pixels - 1) / block_pixels;
  std::vector<Part> parts(blocks);
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    parts[b] = part_of(image.pixels, C, b * block_pixels * C, std::min(pixels, (b + 1) * block_pixels) * C);
  });
  InputStatistics s;
  s.min = parts[0].min;
  s.max = parts[0].max;
  bool on_8bit = true;
  for (const Part& part : parts) {
    for (int c = 0; c < C; ++c) {
      s.min[c] = std::min(s.min[c], part.min[c]);
      s.max[c] = std::max(s.max[c], part.max[c]);
    }
    on_8bit = on_8bit && part.on_8bit;
  }
  // The 16-bit grid is asked only where the 8-bit one fails (an 8-bit
  // sample is a 16-bit one too: 1/255 = 257/65535).
  const auto on_16bit = [&] {
    std::vector<char> block_on(blocks);
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
      bool on = true;
      const std::size_t end = std::min(pixels, (b + 1) * block_pixels) * C;
      for (std::size_t i = b * block_pixels * C; i < end && on; ++i) on = on_code_grid(image.pixels[i], 65535.0);
      block_on[b] = on;
    });
    return std::all_of(block_on.begin(), block_on.end(), [](char on) { return on != 0; });
  };
  s.quantum = on_8bit ? 1 / 255.0 : on_16bit() ? 1 / 65535.0 : 0;
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
