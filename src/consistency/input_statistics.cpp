#include "consistency/input_statistics.hpp"

#include "util/error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <tuple>
#include <utility>
#include <vector>

namespace ddt {

namespace {

// A code c read as the float nearest c / levels is off by up to half a
// float's spacing, 2^-24 of it: up to 0.002 of a code at 16 bits, more
// than the thousandth allowed otherwise (then three in four 16-bit codes
// failed, and 16-bit inputs counted as float ones).
bool on_code_grid(float value, double levels) {
  const double code = value * levels;
  return std::abs(code - std::round(code)) < std::max(1e-3, 4 * std::abs(code) * 0x1p-24);
}

}  // namespace

InputStatistics input_statistics(const Image& image) {
  if (image.empty() || image.channels < 1) throw Error("input statistics of an empty image");
  const int C = image.channels;
  const std::vector<float>& samples = image.pixels;
  // Blocks of whole pixels, each on a thread: min, max and "and" merge in
  // any order to the same result.
  const tbb::blocked_range<std::size_t> pixels(0, samples.size() / C, std::size_t(1) << 16);
  using Range = std::pair<std::vector<float>, std::vector<float>>;  // per channel min, max
  const std::vector<float> first(samples.begin(), samples.begin() + C);
  InputStatistics s;
  std::tie(s.min, s.max) = tbb::parallel_reduce(
      pixels, Range{first, first},
      [&](const tbb::blocked_range<std::size_t>& block, Range range) {
        for (std::size_t p = block.begin(); p < block.end(); ++p)
          for (int c = 0; c < C; ++c) {
            const float v = samples[p * C + c];
            range.first[c] = std::min(range.first[c], v);
            range.second[c] = std::max(range.second[c], v);
          }
        return range;
      },
      [C](Range a, const Range& b) {
        for (int c = 0; c < C; ++c) {
          a.first[c] = std::min(a.first[c], b.first[c]);
          a.second[c] = std::max(a.second[c], b.second[c]);
        }
        return a;
      });
  auto all_on_grid = [&](double levels) {
    return tbb::parallel_reduce(
        pixels, true,
        [&](const tbb::blocked_range<std::size_t>& block, bool on) {
          for (std::size_t i = block.begin() * C; i < block.end() * C && on; ++i) on = on_code_grid(samples[i], levels);
          return on;
        },
        std::logical_and<>());
  };
  // The 16-bit grid is asked only where the 8-bit one fails (an 8-bit
  // sample is a 16-bit one too: 1/255 = 257/65535).
  s.quantum = all_on_grid(255.0) ? 1 / 255.0 : all_on_grid(65535.0) ? 1 / 65535.0 : 0;
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
