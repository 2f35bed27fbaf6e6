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

// Pixels [x0, x1) x [y0, y1) of the first frame.
struct Window {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
Window whole(const Plane& p) { return {0, 0, p.width, p.height}; }

// Mean |a(x, y) - b(x + dx, y + dy)| over the window's pixels whose match
// lies in b (squared: of the squares); infinite when that overlap is under
// half the window on an axis, where a few pixels could match by chance.
double mean_difference(const Plane& a, const Plane& b, int dx, int dy, const Window& w, bool squared = false) {
  const int x0 = std::max(w.x0, -dx), x1 = std::min(w.x1, b.width - dx);
  const int y0 = std::max(w.y0, -dy), y1 = std::min(w.y1, b.height - dy);
  if (2 * (x1 - x0) < w.x1 - w.x0 || 2 * (y1 - y0) < w.y1 - w.y0 || x1 <= x0 || y1 <= y0)
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
Shift best_shift(const Plane& a, const Plane& b, int cx, int cy, int radius, const Window& w) {
  Shift best;
  for (int dy = cy - radius; dy <= cy + radius; ++dy)
    for (int dx = cx - radius; dx <= cx + radius; ++dx) {
      const double cost = mean_difference(a, b, dx, dy, w);
      const bool nearer = std::abs(dx) + std::abs(dy) < std::abs(best.dx) + std::abs(best.dy);
      if (cost < best.cost || (cost == best.cost && nearer)) best = {dx, dy, cost};
    }
  return best;
}

// A frame and its 2x2 box pyramid down to about 32 pixels (level 0 is the
// frame itself).
struct Pyramid {
  const Plane* frame = nullptr;
  std::vector<Plane> halved;
  explicit Pyramid(const Plane& p) : frame(&p) {
    while (std::min(level(levels() - 1).width, level(levels() - 1).height) >= 64)
      halved.push_back(half(level(levels() - 1)));
  }
  int levels() const { return 1 + static_cast<int>(halved.size()); }
  const Plane& level(int l) const { return l == 0 ? *frame : halved[std::size_t(l - 1)]; }
};

Window at_level(const Window& w, int l) { return {w.x0 >> l, w.y0 >> l, w.x1 >> l, w.y1 >> l}; }

// The window's best whole shift, coarse to fine from level `top` (+-4
// there, +-1 at each finer level), then the vertex of the quadratic
// through the mean squared differences at the 3x3 shifts around it
// (parabolic about the minimum for a smooth image; the cross term matters
// where the texture is oriented).
struct Match {
  double dx = 0, dy = 0;
  double cost = 0;  // mean absolute difference at the best whole shift
};
// With `guess`: a search of +-1 about that shift at level 0 alone.
Match match(const Pyramid& a, const Pyramid& b, const Window& w, int top, const Shift* guess = nullptr) {
  Shift s = guess ? best_shift(*a.frame, *b.frame, guess->dx, guess->dy, 1, w)
                  : best_shift(a.level(top), b.level(top), 0, 0, 4, at_level(w, top));
  if (guess) top = 0;
  for (int level = top - 1; level >= 0; --level)
    s = best_shift(a.level(level), b.level(level), 2 * s.dx, 2 * s.dy, 1, at_level(w, level));
  double c[3][3];
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) c[j + 1][i + 1] = mean_difference(*a.frame, *b.frame, s.dx + i, s.dy + j, w, true);
  const double gx = (c[1][2] - c[1][0]) / 2, gy = (c[2][1] - c[0][1]) / 2;
  const double hxx = c[1][2] - 2 * c[1][1] + c[1][0], hyy = c[2][1] - 2 * c[1][1] + c[0][1];
  const double hxy = (c[2][2] - c[2][0] - c[0][2] + c[0][0]) / 4;
  const double det = hxx * hyy - hxy * hxy;
  double ox = 0, oy = 0;
  if (std::isfinite(det) && det > 0 && hxx > 0) {
    ox = std::clamp(-(hyy * gx - hxy * gy) / det, -1.0, 1.0);
    oy = std::clamp(-(hxx * gy - hxy * gx) / det, -1.0, 1.0);
  }
  return {s.dx + ox, s.dy + oy, s.cost};
}

struct PairMotion {
  double dx = 0, dy = 0;
  bool explained = false;
  // The zoom model's fit over the blocks (x' = x + zoom (x - c) + d).
  double zoom = 0, zoom_dx = 0, zoom_dy = 0;
  bool zoom_explained = false;
};

// Mean |a(x + 1, y) - a(x, y)| + |a(x, y + 1) - a(x, y)| over the window:
// below min_block_texture a block's match says nothing of its motion.
double texture(const Plane& a, const Window& w) {
  double sum = 0;
  for (int y = w.y0; y + 1 < w.y1; ++y)
    for (int x = w.x0; x + 1 < w.x1; ++x)
      sum += std::abs(a.at(x + 1, y) - a.at(x, y)) + std::abs(a.at(x, y + 1) - a.at(x, y));
  return sum / std::max(1.0, double(w.x1 - w.x0 - 1) * (w.y1 - w.y0 - 1));
}

// The zoom model fitted to the shifts of a grid of blocks: the least
// squares (zoom, dx, dy) of shift = zoom (centre - c) + d over the blocks
// with texture; then each block matched again about the shift the fit
// predicts for it (+-1 pixel: a periodic texture's match can lock onto
// another period), and the fit made again over the blocks within 0.5
// pixel of it; the pair is explained when they are at least
// min_agreeing_share of the blocks.
void fit_zoom(const Pyramid& a, const Pyramid& b, const DominantMotionOptions& options, PairMotion& m) {
  const Plane& f = *a.frame;
  const int n = options.zoom_blocks;
  const double cx = f.width / 2.0, cy = f.height / 2.0;
  struct Block {
    double px, py, sx, sy;
    Window w;
  };
  std::vector<Block> blocks;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Window w{i * f.width / n, j * f.height / n, (i + 1) * f.width / n, (j + 1) * f.height / n};
      if (w.x1 - w.x0 < 16 || w.y1 - w.y0 < 16 || texture(f, w) < options.min_block_texture) continue;
      int top = 0;  // the coarsest level where the block is still 16 pixels
      while (top + 1 < a.levels() && std::min(w.x1 - w.x0, w.y1 - w.y0) >> (top + 1) >= 16) ++top;
      const Match s = match(a, b, w, top);
      if (!std::isfinite(s.cost)) continue;
      blocks.push_back({(w.x0 + w.x1) / 2.0 - cx, (w.y0 + w.y1) / 2.0 - cy, s.dx, s.dy, w});
    }
  if (blocks.size() < static_cast<std::size_t>(options.min_zoom_blocks)) return;
  std::vector<char> used(blocks.size(), 1);
  // Least squares over the used blocks; false when too few are left.
  auto fit = [&] {
    double spp = 0, spx = 0, spy = 0, sxs = 0, sys = 0, sps = 0, count = 0;
    for (std::size_t k = 0; k < blocks.size(); ++k) {
      if (!used[k]) continue;
      const Block& q = blocks[k];
      spp += q.px * q.px + q.py * q.py, spx += q.px, spy += q.py;
      sxs += q.sx, sys += q.sy, sps += q.px * q.sx + q.py * q.sy, count += 1;
    }
    const double varp = spp - (spx * spx + spy * spy) / count;
    if (count < options.min_zoom_blocks || !(varp > 0)) return false;
    m.zoom = (sps - (spx * sxs + spy * sys) / count) / varp;  // x and y share the zoom
    m.zoom_dx = (sxs - m.zoom * spx) / count;
    m.zoom_dy = (sys - m.zoom * spy) / count;
    return true;
  };
  auto mark_inliers = [&] {
    int inliers = 0;
    for (std::size_t k = 0; k < blocks.size(); ++k) {
      const Block& q = blocks[k];
      used[k] = std::abs(m.zoom * q.px + m.zoom_dx - q.sx) <= 0.5 && std::abs(m.zoom * q.py + m.zoom_dy - q.sy) <= 0.5;
      inliers += used[k];
    }
    return inliers;
  };
  if (!fit()) return;
  mark_inliers();
  if (!fit()) return;
  for (Block& q : blocks) {
    const Shift guess{static_cast<int>(std::lround(m.zoom * q.px + m.zoom_dx)),
                      static_cast<int>(std::lround(m.zoom * q.py + m.zoom_dy))};
    const Match s = match(a, b, q.w, 0, &guess);
    if (std::isfinite(s.cost)) q.sx = s.dx, q.sy = s.dy;
  }
  mark_inliers();
  if (!fit()) return;
  m.zoom_explained = mark_inliers() >= options.min_agreeing_share * double(blocks.size());
}

PairMotion pair_motion(const Plane& a, const Plane& b, const DominantMotionOptions& options) {
  const Pyramid pa(a), pb(b);
  const Match s = match(pa, pb, whole(a), pa.levels() - 1);
  const double unshifted = mean_difference(a, b, 0, 0, whole(a));
  if (unshifted <= 1e-7) return {0, 0, true};
  PairMotion m;
  m.explained = s.cost <= options.max_residual_share * unshifted;
  m.dx = s.dx;
  m.dy = s.dy;
  if (!m.explained) fit_zoom(pa, pb, options, m);
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
  int width = 0, height = 0;
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
      width = first[k].width, height = first[k].height;
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
  const bool translation_agreed = result.agreeing >= options.min_agreeing_share * pairs;
  if (moving && translation_agreed) {
    result.found = true;
    result.dx = to_eighth_pixel(result.median_dx);
    result.dy = to_eighth_pixel(result.median_dy);
    return result;
  }
  // No one translation: the zoom model, where the pairs agree on it.
  std::vector<double> zoom, zoom_dx, zoom_dy;
  for (const PairMotion& m : motion) zoom.push_back(m.zoom), zoom_dx.push_back(m.zoom_dx), zoom_dy.push_back(m.zoom_dy);
  result.median_zoom = median(zoom);
  const double mx = median(zoom_dx), my = median(zoom_dy);
  const double hw = width / 2.0, hh = height / 2.0;
  for (const PairMotion& m : motion)
    result.zoom_agreeing += m.zoom_explained && std::abs(m.zoom - result.median_zoom) * std::hypot(hw, hh) <= 0.5 &&
                            std::abs(m.zoom_dx - mx) <= 0.5 && std::abs(m.zoom_dy - my) <= 0.5;
  // The zoom's own motion at the frame's edges: where it is a pixel a
  // frame or less, what moves faster is a translation, and that is the
  // translation's rules' to take or leave (slow_texture.hpp).
  const double zoom_motion = std::abs(result.median_zoom) * std::max(hw, hh);
  // A zoom held over the whole sequence: within a factor of max_total_zoom.
  const double total = std::abs((frames - 1) * std::log1p(std::max(-0.5, result.median_zoom)));
  const bool zoom_agreed = result.zoom_agreeing >= options.min_agreeing_share * pairs && result.median_zoom > -0.5 &&
                           result.median_zoom < 1 && total <= std::log(options.max_total_zoom);
  if (zoom_motion > options.min_shift && zoom_agreed) {
    result.found = true;
    result.zoom = to_zoom_step(result.median_zoom);
    result.dx = to_eighth_pixel(mx);
    result.dy = to_eighth_pixel(my);
  } else {
    // The pairs agree on a motion too slow to follow (still frames too).
    result.slow = translation_agreed || zoom_agreed;
    result.slow_zoom = !translation_agreed && zoom_agreed;
  }
  return result;
}

}  // namespace ddt
