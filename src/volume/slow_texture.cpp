#include "volume/slow_texture.hpp"

#include "util/error.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace ddt {
namespace {

struct Frames {
  const float* values;
  int width, height, channels;
  std::size_t step;  // samples a frame
  float at(int t, int x, int y, int c) const {
    x = std::clamp(x, 0, width - 1), y = std::clamp(y, 0, height - 1);
    return values[(t * step + static_cast<std::size_t>(y) * width + x) * channels + c];
  }
};

// Per sample of frame t: whether its structure tensor says texture (not
// flat, not an edge).
std::vector<char> textured(const Frames& f, int t, const SlowTextureOptions& options) {
  const int W = f.width, H = f.height;
  std::vector<double> jxx(f.step), jyy(f.step), jxy(f.step);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double a = 0, b = 0, c = 0;
      for (int ch = 0; ch < f.channels; ++ch) {
        const double gx = (double(f.at(t, x + 1, y, ch)) - f.at(t, x - 1, y, ch)) / 2;
        const double gy = (double(f.at(t, x, y + 1, ch)) - f.at(t, x, y - 1, ch)) / 2;
        a += gx * gx, b += gy * gy, c += gx * gy;
      }
      const std::size_t i = static_cast<std::size_t>(y) * W + x;
      jxx[i] = a, jyy[i] = b, jxy[i] = c;
    }
  std::vector<char> result(f.step, 0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      double a = 0, b = 0, c = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::size_t i = static_cast<std::size_t>(std::clamp(y + dy, 0, H - 1)) * W + std::clamp(x + dx, 0, W - 1);
          a += jxx[i], b += jyy[i], c += jxy[i];
        }
      const double trace = a + b;
      const double coherence = trace > 0 ? ((a - b) * (a - b) + 4 * c * c) / (trace * trace) : 1.0;
      result[static_cast<std::size_t>(y) * W + x] = trace > options.min_structure && coherence <= options.max_coherence;
    }
  return result;
}

// The whole-pixel shift of the patch at (x, y) from frame t to t + 1 with
// the least sum of absolute differences: its larger component, or -1 when
// that match is no match (not below match_share of the mean over the
// shifts searched: the motion is beyond the search, or the patch repeats).
int best_shift(const Frames& f, int t, int x, int y, const SlowTextureOptions& options) {
  double best = std::numeric_limits<double>::infinity(), total = 0;
  int best_size = 0, shifts = 0;
  for (int ey = -options.search; ey <= options.search; ++ey)
    for (int ex = -options.search; ex <= options.search; ++ex) {
      double sad = 0;
      for (int dy = -options.patch; dy <= options.patch; ++dy)
        for (int dx = -options.patch; dx <= options.patch; ++dx)
          for (int c = 0; c < f.channels; ++c)
            sad += std::abs(double(f.at(t, x + dx, y + dy, c)) - f.at(t + 1, x + dx + ex, y + dy + ey, c));
      const int size = std::max(std::abs(ex), std::abs(ey));
      if (sad < best || (sad == best && size < best_size)) best = sad, best_size = size;
      total += sad, ++shifts;
    }
  return best <= options.match_share * total / shifts ? best_size : -1;
}

}  // namespace

std::vector<char> slow_texture_samples(const std::vector<float>& values, int width, int height, int frames,
                                       int channels, const SlowTextureOptions& options) {
  if (width < 1 || height < 1 || frames < 1 || channels < 1)
    throw Error("slow texture: the frames must be at least 1x1, one channel");
  const std::size_t step = static_cast<std::size_t>(width) * height;
  if (values.size() != step * frames * channels) throw Error("slow texture: the samples do not match the size");
  const Frames f{values.data(), width, height, channels, step};
  std::vector<std::vector<char>> texture(frames);
  tbb::parallel_for(0, frames, [&](int t) { texture[t] = textured(f, t, options); });
  std::vector<char> slow(step * frames, 0);
  tbb::parallel_for(0, std::max(0, frames - 1), [&](int t) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        if (!texture[t][i] || !texture[t + 1][i]) continue;
        const int shift = best_shift(f, t, x, y, options);
        slow[t * step + i] = shift >= 0 && shift <= options.max_shift;
      }
  });
  return slow;
}

}  // namespace ddt
