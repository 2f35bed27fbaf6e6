#include "eval/edge_sharpness.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace ddt {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Bilinear interpolation of channel c between the pixel samples (centres at
// x + 0.5), the border samples held constant beyond the outermost centres.
double bilinear(const Image& img, double qx, double qy, int c) {
  const double fx = std::clamp(qx - 0.5, 0.0, img.width - 1.0);
  const double fy = std::clamp(qy - 0.5, 0.0, img.height - 1.0);
  const int x0 = std::min(static_cast<int>(fx), img.width - 1), y0 = std::min(static_cast<int>(fy), img.height - 1);
  const int x1 = std::min(x0 + 1, img.width - 1), y1 = std::min(y0 + 1, img.height - 1);
  const double ax = fx - x0, ay = fy - y0;
  const double top = (1 - ax) * img.at(x0, y0, c) + ax * img.at(x1, y0, c);
  const double bottom = (1 - ax) * img.at(x0, y1, c) + ax * img.at(x1, y1, c);
  return (1 - ay) * top + ay * bottom;
}

// Narrows [u_lo, u_hi] to the u with lo <= p + u t <= hi.
void clip_interval(double p, double t, double lo, double hi, double& u_lo, double& u_hi) {
  if (std::abs(t) < 1e-12) {
    if (p < lo || p > hi) u_lo = std::numeric_limits<double>::infinity();
    return;
  }
  double a = (lo - p) / t, b = (hi - p) / t;
  if (a > b) std::swap(a, b);
  u_lo = std::max(u_lo, a);
  u_hi = std::min(u_hi, b);
}

// Position between samples j and j + 1 where the profile passes `level`.
double crossing(const std::vector<double>& d, const std::vector<double>& v, int j, double level) {
  const double dv = v[j + 1] - v[j];
  const double t = dv == 0.0 ? 0.5 : std::clamp((level - v[j]) / dv, 0.0, 1.0);
  return d[j] + t * (d[j + 1] - d[j]);
}

struct Crossings {
  bool found = false;
  double d10 = 0, d50 = 0, d90 = 0;
};

// The crossings of one profile, v normalized so low = 0 and high = 1.
Crossings find_crossings(const std::vector<double>& d, const std::vector<double>& v) {
  Crossings c;
  const int n = static_cast<int>(v.size());
  int j50 = -1;
  for (int j = 0; j + 1 < n; ++j) {
    if (!(v[j] < 0.5 && v[j + 1] >= 0.5)) continue;
    const double at = crossing(d, v, j, 0.5);
    if (j50 < 0 || std::abs(at) < std::abs(c.d50)) {
      j50 = j;
      c.d50 = at;
    }
  }
  if (j50 < 0) return c;
  int j10 = j50;  // towards the low side: the first sample at or below 10 %
  while (j10 >= 0 && v[j10] > 0.1) --j10;
  int j90 = j50 + 1;  // towards the high side: the first sample at or above 90 %
  while (j90 < n && v[j90] < 0.9) ++j90;
  if (j10 < 0 || j90 >= n) return c;
  c.d10 = crossing(d, v, j10, 0.1);
  c.d90 = crossing(d, v, j90 - 1, 0.9);
  c.found = true;
  return c;
}

// out[i] = the best (largest for `max`, else smallest) of in[j * stride],
// |j - i| <= r, 0 <= j < n: a monotonic queue of candidate indices, O(n).
void window_extreme(const float* in, std::ptrdiff_t stride, int n, int r, bool max, float* out,
                    std::vector<int>& queue) {
  queue.resize(n);
  int head = 0, tail = 0, next = 0;
  auto beaten = [&](float kept, float incoming) { return max ? kept <= incoming : kept >= incoming; };
  for (int i = 0; i < n; ++i) {
    for (; next < n && next <= i + r; ++next) {
      while (tail > head && beaten(in[queue[tail - 1] * stride], in[next * stride])) --tail;
      queue[tail++] = next;
    }
    while (queue[head] < i - r) ++head;
    out[i * stride] = in[queue[head] * stride];
  }
}

// The max (or min) of one channel of `img` over the square window of
// half-width r around each pixel, clipped to the image: a plane width x height.
std::vector<float> window_extreme_plane(const Image& img, int c, int r, bool max) {
  const int w = img.width, h = img.height;
  std::vector<float> plane(img.pixel_count()), rows(plane.size()), result(plane.size());
  for (std::size_t i = 0; i < plane.size(); ++i) plane[i] = img.pixels[i * img.channels + c];
  std::vector<int> queue;
  for (int y = 0; y < h; ++y)
    window_extreme(plane.data() + static_cast<std::size_t>(y) * w, 1, w, r, max,
                   rows.data() + static_cast<std::size_t>(y) * w, queue);
  for (int x = 0; x < w; ++x) window_extreme(rows.data() + x, w, h, r, max, result.data() + x, queue);
  return result;
}

}  // namespace

EdgeSharpness measure_edge_sharpness(const Image& img, const StepEdge& edge, double scale,
                                     const EdgeSharpnessOptions& options) {
  if (img.empty() || img.width < 1 || img.height < 1) throw Error("edge sharpness: the image is empty");
  if (options.channel < 0 || options.channel >= img.channels)
    throw Error("edge sharpness: channel " + std::to_string(options.channel) + " of a " +
                std::to_string(img.channels) + "-channel image");
  if (std::abs(std::hypot(edge.nx, edge.ny) - 1.0) > 1e-6) throw Error("edge sharpness: the normal is not unit length");
  if (!(edge.high > edge.low)) throw Error("edge sharpness: the high level is not above the low level");
  if (!(scale > 0) || !(options.spacing > 0) || !(options.step > 0) || !(options.half_length > 0) ||
      !(options.margin >= 0))
    throw Error("edge sharpness: scale, spacing, step and half length must be positive");

  const double reach = options.half_length * scale;  // output pixels
  const double margin = options.margin * scale;
  const double tx = -edge.ny, ty = edge.nx;  // along the edge

  // The u (distance along the edge from the given point) whose profile ends
  // both stay `margin` inside the image.
  double u_lo = -std::numeric_limits<double>::infinity(), u_hi = std::numeric_limits<double>::infinity();
  for (double side : {-1.0, 1.0}) {
    clip_interval(edge.x + side * reach * edge.nx, tx, margin, img.width - margin, u_lo, u_hi);
    clip_interval(edge.y + side * reach * edge.ny, ty, margin, img.height - margin, u_lo, u_hi);
  }
  EdgeSharpness result;
  result.rise_width = result.wobble = result.offset = kNaN;
  if (!(u_hi >= u_lo)) return result;

  const int profile_count = static_cast<int>(std::floor((u_hi - u_lo) / options.spacing)) + 1;
  // Centred in the usable stretch.
  const double u_first = u_lo + 0.5 * (u_hi - u_lo - (profile_count - 1) * options.spacing);
  const double u_last = u_first + (profile_count - 1) * options.spacing;
  const int samples = static_cast<int>(std::ceil(2 * reach / options.step)) + 1;
  std::vector<double> d(samples), v(samples);
  for (int j = 0; j < samples; ++j) d[j] = -reach + 2 * reach * j / (samples - 1);

  const double range = edge.high - edge.low;
  double rise_sum = 0, contour_sum = 0, contour_sq = 0;
  for (int k = 0; k < profile_count; ++k) {
    const double u = u_first + k * options.spacing;
    const double px = edge.x + u * tx, py = edge.y + u * ty;
    for (int j = 0; j < samples; ++j)
      v[j] = (bilinear(img, px + d[j] * edge.nx, py + d[j] * edge.ny, options.channel) - edge.low) / range;
    const Crossings c = find_crossings(d, v);
    if (!c.found) continue;
    ++result.profiles;
    rise_sum += c.d90 - c.d10;
    contour_sum += c.d50;
    contour_sq += c.d50 * c.d50;
  }
  if (result.profiles > 0) {
    result.rise_width = rise_sum / result.profiles / scale;
    result.offset = contour_sum / result.profiles / scale;
    result.wobble = std::sqrt(contour_sq / result.profiles) / scale;
  }

  // Overshoot over the pixels of the band the profiles cover.
  double worst = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double cx = x + 0.5 - edge.x, cy = y + 0.5 - edge.y;
      const double across = cx * edge.nx + cy * edge.ny, along = cx * tx + cy * ty;
      if (std::abs(across) > reach || along < u_first || along > u_last) continue;
      const double value = img.at(x, y, options.channel);
      worst = std::max({worst, value - edge.high, edge.low - value});
    }
  result.overshoot = 100.0 * worst / range;
  return result;
}

double truth_halo(const Image& output, const Image& truth, double scale, const TruthHaloOptions& options) {
  if (output.empty() || truth.empty()) throw Error("truth halo: an image is empty");
  if (output.width != truth.width || output.height != truth.height || output.channels != truth.channels)
    throw Error("truth halo: the output is " + std::to_string(output.width) + "x" + std::to_string(output.height) +
                "x" + std::to_string(output.channels) + ", the truth " + std::to_string(truth.width) + "x" +
                std::to_string(truth.height) + "x" + std::to_string(truth.channels));
  if (!(scale >= 1)) throw Error("truth halo: scale must be >= 1");
  if (!(options.step >= 0) || !(options.step_reach > 0)) throw Error("truth halo: bad step options");
  const int shave = options.shave;
  if (shave < 0 || 2 * shave >= std::min(output.width, output.height))
    throw Error("truth halo: shave " + std::to_string(shave) + " leaves no pixel");

  // floor, with a tolerance, so an integer scale given as 3.9999999 still means 4.
  const int radius = static_cast<int>(std::floor(scale + 1e-9));
  const int step_radius = static_cast<int>(std::floor(options.step_reach * scale + 1e-9));
  const bool local = options.step == 0 && options.local;
  double worst = 0;
  for (int c = 0; c < output.channels; ++c) {
    double channel_step = options.step;
    if (channel_step == 0 && !local) {
      float lowest = truth.pixels[c], highest = truth.pixels[c];
      for (std::size_t i = c; i < truth.pixels.size(); i += truth.channels) {
        lowest = std::min(lowest, truth.pixels[i]);
        highest = std::max(highest, truth.pixels[i]);
      }
      channel_step = static_cast<double>(highest) - lowest;
      if (channel_step < options.min_step) continue;  // a flat channel has no step to ring beside
    }
    const std::vector<float> hi = window_extreme_plane(truth, c, radius, true);
    const std::vector<float> lo = window_extreme_plane(truth, c, radius, false);
    std::vector<float> step_hi, step_lo;
    if (local) {
      step_hi = window_extreme_plane(truth, c, step_radius, true);
      step_lo = window_extreme_plane(truth, c, step_radius, false);
    }
    for (int y = shave; y < output.height - shave; ++y)
      for (int x = shave; x < output.width - shave; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * output.width + x;
        const double step = local ? static_cast<double>(step_hi[i]) - step_lo[i] : channel_step;
        if (local && step < options.min_step) continue;
        const double value = output.at(x, y, c);
        const double excursion = std::max({value - hi[i], static_cast<double>(lo[i]) - value, 0.0});
        worst = std::max(worst, excursion / step);
      }
  }
  return worst;
}

}  // namespace ddt
