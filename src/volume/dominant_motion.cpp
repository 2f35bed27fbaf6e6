#include "volume/dominant_motion.hpp"

#include "util/error.hpp"
#include "util/thread_limit.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

namespace ddt {
namespace {

struct Plane {
  int width = 0, height = 0;
  std::vector<float> v;
  float at(int x, int y) const { return v[static_cast<std::size_t>(y) * width + x]; }
};

Plane luma(const Image& image) {
  Plane p{image.width, image.height, std::vector<float>(static_cast<std::size_t>(image.width) * image.height)};
  const int C = image.channels;
  for (std::size_t i = 0; i < p.v.size(); ++i) {
    float sum = 0;
    for (int c = 0; c < C; ++c) sum += image.pixels[i * C + c];
    p.v[i] = sum / C;
  }
  return p;
}

Plane half(const Plane& p) {
  Plane h{p.width / 2, p.height / 2, {}};
  h.v.resize(static_cast<std::size_t>(h.width) * h.height);
  for (int y = 0; y < h.height; ++y)
    for (int x = 0; x < h.width; ++x)
      h.v[static_cast<std::size_t>(y) * h.width + x] =
          0.25f * (p.at(2 * x, 2 * y) + p.at(2 * x + 1, 2 * y) + p.at(2 * x, 2 * y + 1) + p.at(2 * x + 1, 2 * y + 1));
  return h;
}

// Mean |a(x, y) - b(x + dx, y + dy)| over the overlap (squared: of the
// squares); infinite when the overlap is under half the frame on an axis,
// where a few pixels could match by chance.
double mean_difference(const Plane& a, const Plane& b, int dx, int dy, bool squared = false) {
  const int x0 = std::max(0, -dx), x1 = std::min(a.width, a.width - dx);
  const int y0 = std::max(0, -dy), y1 = std::min(a.height, a.height - dy);
  if (2 * (x1 - x0) < a.width || 2 * (y1 - y0) < a.height || x1 <= x0 || y1 <= y0)
    return std::numeric_limits<double>::infinity();
  double sum = 0;
  const int n = x1 - x0;
  for (int y = y0; y < y1; ++y) {
    const float* ra = a.v.data() + static_cast<std::size_t>(y) * a.width + x0;
    const float* rb = b.v.data() + static_cast<std::size_t>(y + dy) * b.width + (x0 + dx);
    if (squared)
      for (int i = 0; i < n; ++i) sum += double(ra[i] - rb[i]) * (ra[i] - rb[i]);
    else
      for (int i = 0; i < n; ++i) sum += std::abs(ra[i] - rb[i]);
  }
  return sum / (double(x1 - x0) * (y1 - y0));
}

struct Shift {
  int dx = 0, dy = 0;
  double cost = std::numeric_limits<double>::infinity();
};

// The least difference over shifts within radius of (cx, cy); ties to the
// shift nearer zero, so flat frames stay unshifted.
Shift best_shift(const Plane& a, const Plane& b, int cx, int cy, int radius) {
  Shift best;
  for (int dy = cy - radius; dy <= cy + radius; ++dy)
    for (int dx = cx - radius; dx <= cx + radius; ++dx) {
      const double cost = mean_difference(a, b, dx, dy);
      const bool nearer = std::abs(dx) + std::abs(dy) < std::abs(best.dx) + std::abs(best.dy);
      if (cost < best.cost || (cost == best.cost && nearer)) best = {dx, dy, cost};
    }
  return best;
}

struct PairMotion {
  double dx = 0, dy = 0;
  bool explained = false;
};

PairMotion pair_motion(const Plane& a, const Plane& b, const DominantMotionOptions& options) {
  std::vector<Plane> pa, pb;  // the halved levels (level 0 is a, b themselves)
  auto level_a = [&](std::size_t l) -> const Plane& { return l == 0 ? a : pa[l - 1]; };
  auto level_b = [&](std::size_t l) -> const Plane& { return l == 0 ? b : pb[l - 1]; };
  while (std::min(level_a(pa.size()).width, level_a(pa.size()).height) >= 64) {
    pa.push_back(half(level_a(pa.size())));
    pb.push_back(half(level_b(pb.size())));
  }
  Shift s = best_shift(level_a(pa.size()), level_b(pb.size()), 0, 0, 4);
  for (int level = static_cast<int>(pa.size()) - 1; level >= 0; --level)
    s = best_shift(level_a(level), level_b(level), 2 * s.dx, 2 * s.dy, 1);
  const double unshifted = mean_difference(a, b, 0, 0);
  if (unshifted <= 1e-7) return {0, 0, true};
  PairMotion m;
  m.explained = s.cost <= options.max_residual_share * unshifted;
  // The vertex of the quadratic through the mean squared differences at
  // the 3x3 shifts around the best (parabolic about the minimum for a
  // smooth image; the cross term matters where the texture is oriented).
  double c[3][3];
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) c[j + 1][i + 1] = mean_difference(a, b, s.dx + i, s.dy + j, true);
  const double gx = (c[1][2] - c[1][0]) / 2, gy = (c[2][1] - c[0][1]) / 2;
  const double hxx = c[1][2] - 2 * c[1][1] + c[1][0], hyy = c[2][1] - 2 * c[1][1] + c[0][1];
  const double hxy = (c[2][2] - c[2][0] - c[0][2] + c[0][0]) / 4;
  const double det = hxx * hyy - hxy * hxy;
  double ox = 0, oy = 0;
  if (std::isfinite(det) && det > 0 && hxx > 0) {
    ox = std::clamp(-(hyy * gx - hxy * gy) / det, -1.0, 1.0);
    oy = std::clamp(-(hxx * gy - hxy * gx) / det, -1.0, 1.0);
  }
  m.dx = s.dx + ox;
  m.dy = s.dy + oy;
  return m;
}

double median(std::vector<double> x) {
  const std::size_t n = x.size();
  std::nth_element(x.begin(), x.begin() + n / 2, x.end());
  const double upper = x[n / 2];
  if (n % 2) return upper;
  return 0.5 * (upper + *std::max_element(x.begin(), x.begin() + n / 2));
}

}  // namespace

DominantMotion dominant_motion(int frames, const std::function<Image(int)>& frame,
                               const DominantMotionOptions& options) {
  DominantMotion result;
  if (frames < 2 || options.max_pairs < 1) return result;
  const int pairs = std::min(options.max_pairs, frames - 1);
  // Pairs are matched a few at a time (one a thread), so that the planes
  // held are those of a batch, not of every pair.
  const int batch = allowed_threads();
  std::vector<PairMotion> motion(pairs);
  Plane last_read;    // the second frame of the batch before
  int previous = -2;  // the frame before the last one read
  for (int i0 = 0; i0 < pairs; i0 += batch) {
    const int count = std::min(batch, pairs - i0);
    std::vector<Plane> first(count), second(count);
    for (int k = 0; k < count; ++k) {
      // Evenly spaced, at least a frame apart: the frames come in order.
      const int i = i0 + k;
      const int t = pairs == 1 ? 0 : static_cast<int>(std::lround(double(i) * (frames - 2) / (pairs - 1)));
      first[k] = t != previous + 1 ? luma(frame(t)) : k > 0 ? second[k - 1] : std::move(last_read);
      second[k] = luma(frame(t + 1));
      previous = t;
      if (first[k].width != second[k].width || first[k].height != second[k].height || first[k].v.empty())
        throw Error("dominant_motion: frames " + std::to_string(t) + " and " + std::to_string(t + 1) +
                    " differ in size");
    }
    tbb::parallel_for(0, count, [&](int k) { motion[i0 + k] = pair_motion(first[k], second[k], options); });
    last_read = std::move(second[count - 1]);
  }
  std::vector<double> dx, dy;
  for (const PairMotion& m : motion) dx.push_back(m.dx), dy.push_back(m.dy);
  result.pairs = pairs;
  result.median_dx = median(dx);
  result.median_dy = median(dy);
  for (const PairMotion& m : motion)
    result.agreeing += m.explained && std::abs(m.dx - result.median_dx) <= 0.5 &&
                       std::abs(m.dy - result.median_dy) <= 0.5;
  const bool moving = std::max(std::abs(result.median_dx), std::abs(result.median_dy)) > options.min_shift;
  if (moving && result.agreeing >= options.min_agreeing_share * pairs) {
    result.found = true;
    result.dx = to_eighth_pixel(result.median_dx);
    result.dy = to_eighth_pixel(result.median_dy);
  }
  return result;
}

}  // namespace ddt
