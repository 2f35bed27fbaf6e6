#include "consistency/halo_limit.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace ddt {

FootprintPixels footprint_pixels(int W, int H, int out_w, int out_h) {
  const double sx = static_cast<double>(out_w) / W, sy = static_cast<double>(out_h) / H;
  FootprintPixels f;
  f.first_x.resize(W + 1);
  f.first_y.resize(H + 1);
  for (int x = 0; x <= W; ++x) f.first_x[x] = std::min(out_w, static_cast<int>(std::ceil(x * sx - 0.5)));
  for (int y = 0; y <= H; ++y) f.first_y[y] = std::min(out_h, static_cast<int>(std::ceil(y * sy - 0.5)));
  return f;
}

// A bright rim beside a dark line, or a dark one beside a bright line, lies
// outside these bounds: that is the halo; and a bright gap between two dark
// strokes gets no brighter than the background seen within two pixels.
std::pair<float, float> halo_bounds(const Image& src, int x, int y, int c, float image_min, float image_max) {
  const float centre = src.at(x, y, c);
  float lo3 = centre, hi3 = centre, lo5 = centre, hi5 = centre;
  bool strict_min3 = true, strict_max3 = true, strict_min5 = true, strict_max5 = true;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int nx = std::clamp(x + dx, 0, src.width - 1), ny = std::clamp(y + dy, 0, src.height - 1);
      if (nx == x && ny == y) continue;
      const float v = src.at(nx, ny, c);
      const bool inner = std::abs(dx) <= 1 && std::abs(dy) <= 1;
      if (inner) {
        lo3 = std::min(lo3, v);
        hi3 = std::max(hi3, v);
        strict_min3 = strict_min3 && v > centre;
        strict_max3 = strict_max3 && v < centre;
      }
      lo5 = std::min(lo5, v);
      hi5 = std::max(hi5, v);
      strict_min5 = strict_min5 && v > centre;
      strict_max5 = strict_max5 && v < centre;
    }
  const float lo = !strict_min3 ? lo3 : strict_min5 ? image_min : lo5;
  const float hi = !strict_max3 ? hi3 : strict_max5 ? image_max : hi5;
  return {lo, hi};
}

double mean_keeping_shift(const std::vector<float>& o, double mean, double lo, double hi) {
  if (o.empty()) return 0;
  const auto [omin, omax] = std::minmax_element(o.begin(), o.end());
  double a = std::isfinite(lo) ? lo - *omax : -(*omax - *omin) - 1;
  double b = std::isfinite(hi) ? hi - *omin : (*omax - *omin) + 1;
  double t = 0;
  for (int it = 0; it < 60; ++it) {
    double m = 0;
    int free = 0;
    for (float v : o) {
      const double x = v + t;
      if (x <= lo) m += lo;
      else if (x >= hi) m += hi;
      else m += x, ++free;
    }
    const double gap = mean - m / o.size();
    if (std::abs(gap) < 1e-9) break;
    (gap > 0 ? a : b) = t;
    const double next = free > 0 ? t + gap * o.size() / free : 0.5 * (a + b);
    t = next > a && next < b ? next : 0.5 * (a + b);
  }
  return t;
}

long long limit_halos(Image& out, const Image& src) {
  const FootprintPixels f = footprint_pixels(src.width, src.height, out.width, out.height);
  std::vector<float> image_min(src.channels, INFINITY), image_max(src.channels, -INFINITY);
  for (std::size_t i = 0; i < src.pixels.size(); ++i) {
    image_min[i % src.channels] = std::min(image_min[i % src.channels], src.pixels[i]);
    image_max[i % src.channels] = std::max(image_max[i % src.channels], src.pixels[i]);
  }
  std::atomic<long long> limited{0};
  tbb::parallel_for(0, src.height, [&](int y) {
    std::vector<float> o;
    for (int x = 0; x < src.width; ++x)
      for (int c = 0; c < src.channels; ++c) {
        o.clear();
        for (int Y = f.first_y[y]; Y < f.first_y[y + 1]; ++Y)
          for (int X = f.first_x[x]; X < f.first_x[x + 1]; ++X) o.push_back(out.at(X, Y, c));
        if (o.empty()) continue;
        const auto [omin, omax] = std::minmax_element(o.begin(), o.end());
        // The bounds contain the 3x3 range: most footprints stay inside it.
        float lo3 = src.at(x, y, c), hi3 = lo3;
        for (int ny = std::max(0, y - 1); ny <= std::min(src.height - 1, y + 1); ++ny)
          for (int nx = std::max(0, x - 1); nx <= std::min(src.width - 1, x + 1); ++nx)
            lo3 = std::min(lo3, src.at(nx, ny, c)), hi3 = std::max(hi3, src.at(nx, ny, c));
        if (*omin >= lo3 && *omax <= hi3) continue;
        const auto [lo, hi] = halo_bounds(src, x, y, c, image_min[c], image_max[c]);
        if (*omin >= lo && *omax <= hi) continue;
        double mean = 0;
        for (float v : o) mean += v;
        mean /= o.size();
        // The mean is the input pixel, inside [lo, hi] up to the solver's
        // tolerance; a mean on a bound leaves one answer, the flat bound.
        if (!(mean >= lo - 1e-5 && mean <= hi + 1e-5)) continue;  // cannot hold: keep the consistent values
        const double t = mean_keeping_shift(o, std::clamp(mean, double(lo), double(hi)), lo, hi);
        for (int Y = f.first_y[y]; Y < f.first_y[y + 1]; ++Y)
          for (int X = f.first_x[x]; X < f.first_x[x + 1]; ++X) {
            float& v = out.at(X, Y, c);
            v = static_cast<float>(std::clamp(v + t, double(lo), double(hi)));
          }
        ++limited;
      }
  });
  return limited;
}

}  // namespace ddt
