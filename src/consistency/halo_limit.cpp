#include "consistency/halo_limit.hpp"

#include "util/error.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
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
  const bool inside = x >= 2 && y >= 2 && x + 2 < src.width && y + 2 < src.height;  // nothing clamped
  const std::ptrdiff_t step_x = src.channels, step_y = std::ptrdiff_t(src.width) * src.channels;
  const float* p = &src.pixels[src.index(x, y)] + c;
  auto at = [&](int dx, int dy) {
    if (inside) return p[dy * step_y + dx * step_x];
    return src.at(std::clamp(x + dx, 0, src.width - 1), std::clamp(y + dy, 0, src.height - 1), c);
  };
  auto is_centre = [&](int dx, int dy) {  // a clamped neighbour that lands on the centre is not one
    return !inside && std::clamp(x + dx, 0, src.width - 1) == x && std::clamp(y + dy, 0, src.height - 1) == y;
  };
  // The 3x3 first: the 5x5's outer ring matters only for a strict 3x3
  // extremum, which few pixels are.
  float lo = centre, hi = centre;
  bool strict_min = true, strict_max = true;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if ((dx == 0 && dy == 0) || is_centre(dx, dy)) continue;
      const float v = at(dx, dy);
      lo = std::min(lo, v), hi = std::max(hi, v);
      strict_min = strict_min && v > centre;
      strict_max = strict_max && v < centre;
    }
  if (!strict_min && !strict_max) return {lo, hi};
  float lo5 = lo, hi5 = hi;
  bool strict_min5 = strict_min, strict_max5 = strict_max;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      if ((std::abs(dx) <= 1 && std::abs(dy) <= 1) || is_centre(dx, dy)) continue;
      const float v = at(dx, dy);
      lo5 = std::min(lo5, v), hi5 = std::max(hi5, v);
      strict_min5 = strict_min5 && v > centre;
      strict_max5 = strict_max5 && v < centre;
    }
  return {strict_min ? (strict_min5 ? image_min : lo5) : lo, strict_max ? (strict_max5 ? image_max : hi5) : hi};
}

namespace {

// The sum of clamp(v + t, lo, hi) and how many values it leaves unclamped.
// Without branches (which value is clamped is unpredictable): the same
// sums, as lo <= hi.
double clamped_sum(const std::vector<float>& o, double t, double lo, double hi, int& free) {
  double m = 0;
  free = 0;
  for (float v : o) {
    const double x = v + t;
    m += std::min(std::max(x, lo), hi);
    free += (x > lo) & (x < hi);
  }
  return m;
}

}  // namespace

double mean_keeping_shift(const std::vector<float>& o, double mean, double lo, double hi) {
  if (o.empty()) return 0;
  const double n = static_cast<double>(o.size()), target = mean * n;
  const auto [omin, omax] = std::minmax_element(o.begin(), o.end());
  // Shifted by a, every value is at most the mean, and so is every clamped
  // one (mean >= lo); by b every one at least: the shift lies in [a, b].
  double a = mean - *omax, b = mean - *omin;
  // Two Newton steps from 0 on the unclamped values' count: most
  // footprints end here.
  double t = 0;
  for (int step = 0; step < 3; ++step) {
    int free = 0;
    const double gap = (target - clamped_sum(o, t, lo, hi, free)) / n;
    if (std::abs(gap) < 1e-9) return t;
    (gap > 0 ? a : b) = t;
    const double next = free > 0 ? t + gap * n / free : NAN;
    if (step == 2 || !(next > a && next < b)) break;
    t = next;
  }
  // The sum is linear in t between the breakpoints lo - v and hi - v:
  // bisect over the sorted breakpoints inside (a, b) for the piece that
  // holds the target, then interpolate on it.
  // On the stack for footprints of up to 64 pixels (x8 and below): this
  // runs for about 40 % of the limited footprints.
  constexpr std::size_t stack_values = 64;
  std::array<double, 2 * stack_values + 2> on_stack;
  std::vector<double> on_heap;
  double* points = on_stack.data();
  if (o.size() > stack_values) {
    on_heap.resize(2 * o.size() + 2);
    points = on_heap.data();
  }
  std::size_t count = 0;
  points[count++] = a;
  for (float v : o)
    for (const double bound : {lo, hi})
      if (bound - v > a && bound - v < b) points[count++] = bound - v;
  points[count++] = b;
  std::sort(points, points + count);
  std::size_t i = 0, j = count - 1;  // sum(points[i]) <= target <= sum(points[j])
  int unused = 0;
  double mi = clamped_sum(o, points[i], lo, hi, unused), mj = clamped_sum(o, points[j], lo, hi, unused);
  while (j - i > 1) {
    const std::size_t k = (i + j) / 2;
    const double mk = clamped_sum(o, points[k], lo, hi, unused);
    if (mk < target) {
      i = k, mi = mk;
    } else {
      j = k, mj = mk;
    }
  }
  return mj > mi ? points[i] + (target - mi) / (mj - mi) * (points[j] - points[i]) : points[j];
}

HaloLimiter::HaloLimiter(const Image& src, const InputStatistics& statistics, const RowBand& band)
    : src_(src), statistics_(statistics), band_(band) {}

long long HaloLimiter::limit(Image& out, int first_row, int end_row) const {
  const Image& src = src_;
  const std::vector<float>&image_min = statistics_.min, &image_max = statistics_.max;
  const int top = band_.src_top, out_origin = band_.out_origin;
  const int H = band_.image_height > 0 ? band_.image_height : src.height;
  const int out_h = band_.out_height > 0 ? band_.out_height : out.height;
  const FootprintPixels f = footprint_pixels(src.width, H, out.width, out_h);
  const int C = src.channels;
  if (static_cast<int>(image_min.size()) != C) throw Error("halo limit: statistics of another image");
  // Footprints of the band's rows whose output rows `out` holds.
  end_row = std::min(end_row < 0 ? H : end_row, top + src.height);
  first_row = std::max(first_row, top);
  while (first_row < end_row && f.first_y[first_row] < out_origin) ++first_row;
  while (end_row > first_row && f.first_y[end_row] > out_origin + out.height) --end_row;
  if (first_row >= end_row) return 0;
  std::atomic<long long> limited{0};
  tbb::parallel_for(first_row, end_row, [&](int global_y) {
    const int y = global_y - top;  // the band's own row
    // A footprint's range in every channel is found in one pass over its
    // pixels; only a channel that leaves its 3x3 range is gathered.
    std::vector<float> o;
    std::vector<float> lo3(C), hi3(C), omin(C), omax(C);
    long long count = 0;
    const int y0 = std::max(0, y - 1), y1 = std::min(src.height - 1, y + 1);
    const int Y0 = f.first_y[global_y] - out_origin, Y1 = f.first_y[global_y + 1] - out_origin;
    for (int x = 0; x < src.width; ++x) {
      const int X0 = f.first_x[x], X1 = f.first_x[x + 1];
      const std::size_t n = static_cast<std::size_t>(X1 - X0) * (Y1 - Y0);
      if (n == 0) continue;
      {
        const float* first = &out.pixels[out.index(X0, Y0)];
        for (int c = 0; c < C; ++c) omin[c] = omax[c] = first[c];
        for (int Y = Y0; Y < Y1; ++Y) {
          const float* p = &out.pixels[out.index(X0, Y)];
          for (int X = X0; X < X1; ++X, p += C)
            for (int c = 0; c < C; ++c) omin[c] = std::min(omin[c], p[c]), omax[c] = std::max(omax[c], p[c]);
        }
      }
      for (int c = 0; c < C; ++c) lo3[c] = hi3[c] = src.at(x, y, c);
      for (int ny = y0; ny <= y1; ++ny)
        for (int nx = std::max(0, x - 1); nx <= std::min(src.width - 1, x + 1); ++nx) {
          const float* p = &src.pixels[src.index(nx, ny)];
          for (int c = 0; c < C; ++c) lo3[c] = std::min(lo3[c], p[c]), hi3[c] = std::max(hi3[c], p[c]);
        }
      for (int c = 0; c < C; ++c) {
        // The bounds contain the 3x3 range: most footprints stay inside it.
        if (omin[c] >= lo3[c] && omax[c] <= hi3[c]) continue;
        const auto [lo, hi] = halo_bounds(src, x, y, c, image_min[c], image_max[c]);
        if (omin[c] >= lo && omax[c] <= hi) continue;
        o.resize(n);
        std::size_t k = 0;
        for (int Y = Y0; Y < Y1; ++Y)
          for (int X = X0; X < X1; ++X, ++k) o[k] = out.at(X, Y, c);
        double mean = 0;
        for (std::size_t i = 0; i < n; ++i) mean += o[i];
        mean /= n;
        // The mean is the input pixel, inside [lo, hi] up to the solver's
        // tolerance; a mean on a bound leaves one answer, the flat bound.
        if (!(mean >= lo - 1e-5 && mean <= hi + 1e-5)) continue;  // cannot hold: keep the consistent values
        const double t = mean_keeping_shift(o, std::clamp(mean, double(lo), double(hi)), lo, hi);
        k = 0;
        for (int Y = Y0; Y < Y1; ++Y)
          for (int X = X0; X < X1; ++X, ++k)
            out.at(X, Y, c) = static_cast<float>(std::clamp(o[k] + t, double(lo), double(hi)));
        ++count;
      }
    }
    limited += count;
  });
  return limited;
}

}  // namespace ddt
