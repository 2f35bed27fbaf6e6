#include "consistency/step_edges.hpp"

#include "consistency/halo_limit.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <vector>

namespace ddt {

double rectangle_coverage(double s, double p, double q) {
  if (p < q) std::swap(p, q);
  const double half = 0.5 * (p + q);
  if (s <= -half) return 0;
  if (s >= half) return 1;
  const double flat = 0.5 * (p - q);
  if (s < -flat) {
    const double u = s + half;
    return u * u / (2 * p * q);
  }
  if (s > flat) {
    const double u = half - s;
    return 1 - u * u / (2 * p * q);
  }
  return 0.5 + s / p;
}

namespace {

constexpr int window = 9;  // the 3x3 input pixels around a footprint
constexpr int max_channels = 16;

// One straight edge and, per channel, the levels behind it (a) and on its
// normal's side (b).
struct EdgeFit {
  double angle = 0, offset = 0;  // normal (cos, sin); the line is n . p = offset
  std::array<double, max_channels> a{}, b{};
  double misfit = INFINITY;  // largest |model - value| over the window and channels
};

struct Window {
  int C = 1;
  std::array<double, window> cx{}, cy{};             // pixel centres
  std::array<double, window * max_channels> value{};  // [k * C + c]
};

using Residuals = std::array<double, window * max_channels>;

// The misfit of the line (angle, offset), with each channel's levels the
// least-squares ones for it; the residuals model - value in `r`. Returns
// the sum of their squares, or infinity where the line leaves every pixel
// on one side (the levels are then undetermined).
double evaluate(const Window& w, double angle, double offset, EdgeFit& fit, Residuals& r) {
  const double nx = std::cos(angle), ny = std::sin(angle);
  std::array<double, window> share{};
  double s1 = 0, s2 = 0;
  for (int k = 0; k < window; ++k) {
    share[k] = rectangle_coverage(nx * w.cx[k] + ny * w.cy[k] - offset, std::abs(nx), std::abs(ny));
    s1 += share[k];
    s2 += share[k] * share[k];
  }
  const double det = window * s2 - s1 * s1;
  if (!(det > 1e-9)) return INFINITY;
  fit.angle = angle;
  fit.offset = offset;
  fit.misfit = 0;
  double sum = 0;
  for (int c = 0; c < w.C; ++c) {
    double v1 = 0, vs = 0;
    for (int k = 0; k < window; ++k) v1 += w.value[k * w.C + c], vs += w.value[k * w.C + c] * share[k];
    // v = a + (b - a) share, least squares in (a, b - a).
    const double step = (window * vs - s1 * v1) / det, a = (v1 - step * s1) / window;
    fit.a[c] = a;
    fit.b[c] = a + step;
    for (int k = 0; k < window; ++k) {
      const double e = a + step * share[k] - w.value[k * w.C + c];
      r[k * w.C + c] = e;
      sum += e * e;
      fit.misfit = std::max(fit.misfit, std::abs(e));
    }
  }
  return sum;
}

// Fits one edge to the window: a start from the gradient of channel `main`
// and the centre pixel's share, then damped Gauss-Newton steps in
// (angle, offset). `allowed`: the misfit the caller accepts; a fit far
// above it is given up early (returned with an infinite misfit).
EdgeFit fit_edge(const Window& w, int main, double lo, double hi, double allowed) {
  EdgeFit none;
  auto v = [&](int dx, int dy) { return w.value[((dy + 1) * 3 + dx + 1) * w.C + main]; };
  const double gx = (v(1, -1) + 2 * v(1, 0) + v(1, 1)) - (v(-1, -1) + 2 * v(-1, 0) + v(-1, 1));
  const double gy = (v(-1, 1) + 2 * v(0, 1) + v(1, 1)) - (v(-1, -1) + 2 * v(0, -1) + v(1, -1));
  if (gx == 0 && gy == 0) return none;
  const double angle0 = std::atan2(gy, gx), nx = std::cos(angle0), ny = std::sin(angle0);
  // A straight edge's shares grow along its normal: texture that does not
  // is turned away before any fitting (the start's normal is a few degrees
  // off, hence the slack).
  std::array<int, window> order{};
  for (int k = 0; k < window; ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](int i, int j) {
    return nx * w.cx[i] + ny * w.cy[i] < nx * w.cx[j] + ny * w.cy[j];
  });
  const double slack = 0.15 * (hi - lo);
  double highest = -INFINITY;
  for (int k : order) {
    const double value = w.value[k * w.C + main];
    if (value < highest - slack) return none;
    highest = std::max(highest, value);
  }
  // The centre's share of b's side fixes the offset along that normal.
  const double share = std::clamp((v(0, 0) - lo) / (hi - lo), 0.0, 1.0);
  const double at_centre = nx * w.cx[4] + ny * w.cy[4];
  double below = at_centre - 1, above = at_centre + 1;  // share falls as the offset grows
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (below + above);
    (rectangle_coverage(at_centre - mid, std::abs(nx), std::abs(ny)) > share ? below : above) = mid;
  }
  std::array<double, 2> x{angle0, 0.5 * (below + above)};
  Residuals r{}, r1{};
  EdgeFit fit;
  double f = evaluate(w, x[0], x[1], fit, r);
  if (!std::isfinite(f) || fit.misfit > 10 * allowed) return none;
  const int n = window * w.C;
  double lambda = 1e-3;
  for (int it = 0; it < 30 && f > 1e-14; ++it) {
    // Most windows that reach the fit are texture, whose steps shrink the
    // misfit slowly; no fit still 5x the allowed misfit after 3 steps, or
    // 3x after 5, was accepted on the images measured (docs/consistency.md).
    if ((it >= 3 && fit.misfit > 5 * allowed) || (it >= 5 && fit.misfit > 3 * allowed)) return none;
    // Jacobian by forward differences from the residuals at x: the misfit
    // is piecewise smooth, and an error of O(h) in J only slows the steps
    // (each is kept only where it lowers the misfit).
    // (J and rp are left uninitialized: only their first n entries are
    // written and read, and zeroing them all cost more than the fit.)
    std::array<Residuals, 2> J;
    constexpr double h = 1e-6;
    bool ok = true;
    for (int j = 0; j < 2 && ok; ++j) {
      std::array<double, 2> xp = x;
      xp[j] += h;
      Residuals rp;
      EdgeFit scratch;
      ok = std::isfinite(evaluate(w, xp[0], xp[1], scratch, rp));
      if (ok)
        for (int i = 0; i < n; ++i) J[j][i] = (rp[i] - r[i]) / h;
    }
    if (!ok) break;
    double a00 = 0, a01 = 0, a11 = 0, g0 = 0, g1 = 0;
    for (int i = 0; i < n; ++i) {
      a00 += J[0][i] * J[0][i];
      a01 += J[0][i] * J[1][i];
      a11 += J[1][i] * J[1][i];
      g0 += J[0][i] * r[i];
      g1 += J[1][i] * r[i];
    }
    bool improved = false, converged = false;
    for (int tries = 0; tries < 8 && !improved; ++tries) {
      const double d00 = a00 * (1 + lambda) + 1e-12, d11 = a11 * (1 + lambda) + 1e-12;
      const double det = d00 * d11 - a01 * a01;
      if (!(det > 0)) break;
      const std::array<double, 2> step{-(d11 * g0 - a01 * g1) / det, -(d00 * g1 - a01 * g0) / det};
      EdgeFit trial;
      const double f1 = evaluate(w, x[0] + step[0], x[1] + step[1], trial, r1);
      if (f1 < f) {
        // A step below 1e-9 (radians, input pixels) moves no drawn value
        // by a float's rounding: converged.
        converged = std::abs(step[0]) < 1e-9 && std::abs(step[1]) < 1e-9;
        fit = trial;
        x = {x[0] + step[0], x[1] + step[1]};
        f = f1;
        r = r1;
        lambda *= 0.3;
        improved = true;
      } else {
        lambda *= 10;
      }
    }
    if (!improved || converged) break;
  }
  return fit;
}

// The largest misfit of the fitted edge, levels kept, over the 5x5 input
// pixels around (x, y): a second feature within two pixels (the far side of
// a thin line, a corner, the image's own border stripe) shows here.
// (x, y) the whole image's pixel; src holds rows from `top`.
double misfit_5x5(const Image& src, int top, int x, int y, const EdgeFit& fit) {
  const double nx = std::cos(fit.angle), ny = std::sin(fit.angle);
  double worst = 0;
  for (int py = y - 2; py <= y + 2; ++py)
    for (int px = x - 2; px <= x + 2; ++px) {
      const double share =
          rectangle_coverage(nx * (px + 0.5) + ny * (py + 0.5) - fit.offset, std::abs(nx), std::abs(ny));
      for (int c = 0; c < src.channels; ++c)
        worst = std::max(worst, std::abs(fit.a[c] + (fit.b[c] - fit.a[c]) * share - src.at(px, py - top, c)));
    }
  return worst;
}

// False when a pixel of the 5x5 window lies farther than `reach` outside
// its channel's 3x3 range [lo, hi]: then no fit can be drawn. A drawn fit
// has its levels within `allowed` of that range and every 5x5 pixel within
// the reach tolerance of a value between its levels, so `reach` is the sum
// of the two (and a millionth of the step for rounding). Tested before the
// fit, which most windows of a photograph reach only to fail the 5x5 test.
bool within_reach(const Image& src, int top, int x, int y, const std::array<double, max_channels>& lo,
                  const std::array<double, max_channels>& hi, double reach) {
  for (int py = y - 2; py <= y + 2; ++py)
    for (int px = x - 2; px <= x + 2; ++px)
      for (int c = 0; c < src.channels; ++c) {
        const double v = src.at(px, py - top, c);
        if (v < lo[c] - reach || v > hi[c] + reach) return false;
      }
  return true;
}

}  // namespace

StepEdgeRenderer::StepEdgeRenderer(const Image& src, const InputStatistics& statistics, const RowBand& band,
                                   const StepEdgeOptions& options)
    : src_(src), band_(band), options_(options) {
  const int H = band.image_height > 0 ? band.image_height : src.height;
  if (src.width < 5 || H < 5 || src.channels > max_channels || statistics.min.empty()) return;
  min_step_ = options.min_step_codes * statistics.quantum;
  if (statistics.quantum == 0) {
    const float lo = *std::min_element(statistics.min.begin(), statistics.min.end());
    const float hi = *std::max_element(statistics.max.begin(), statistics.max.end());
    min_step_ = options.min_step_share * (hi - lo);
  }
  rounding_ = 0.5 * statistics.quantum;
}

long long render_step_edges(Image& out, const Image& src, const StepEdgeOptions& options) {
  return StepEdgeRenderer(src, input_statistics(src), {}, options).render(out);
}

long long StepEdgeRenderer::render(Image& out, int first_row, int end_row) const {
  const Image& src = src_;
  const StepEdgeOptions& options = options_;
  const int top = band_.src_top, out_origin = band_.out_origin;
  const int W = src.width, H = band_.image_height > 0 ? band_.image_height : src.height, C = src.channels;
  const int out_h = band_.out_height > 0 ? band_.out_height : out.height;
  const double min_step = min_step_, rounding = rounding_;
  if (!(min_step > 0)) return 0;  // a flat image, or one too small or with too many channels
  const FootprintPixels f = footprint_pixels(W, H, out.width, out_h);
  const double pw = static_cast<double>(W) / out.width, ph = static_cast<double>(H) / out_h;  // output pixel size
  // Footprints with the whole 5x5 window inside the image and the band,
  // whose output rows `out` holds.
  int first = std::max({2, first_row, top + 2}), end = std::min({H - 2, end_row < 0 ? H : end_row, top + src.height - 2});
  while (first < end && f.first_y[first] < out_origin) ++first;
  while (end > first && f.first_y[end] > out_origin + out.height) --end;
  if (first >= end) return 0;
  std::atomic<long long> drawn{0};
  tbb::parallel_for(first, end, [&](int y) {
    Window w;
    w.C = C;
    std::vector<float> o;
    const std::ptrdiff_t row_stride = std::ptrdiff_t(W) * C;
    for (int x = 2; x < W - 2; ++x) {
      // The 3x3 window read straight from the rows; the Window (positions
      // and values in double) is filled only for the few pixels that pass
      // the tests below, which turn away almost every pixel of a photograph.
      const float* centre_pixel = &src.pixels[src.index(x, y - top)];
      auto window_value = [&](int k, int c) -> double {
        return centre_pixel[(k / 3 - 1) * row_stride + (k % 3 - 1) * C + c];
      };
      // The channel with the largest step decides whether this is an edge
      // pixel at all: strictly between the levels around it.
      int main = -1;
      double main_step = min_step, lo_main = 0, hi_main = 0;
      std::array<double, max_channels> lo, hi;  // the first C entries, set below
      for (int c = 0; c < C; ++c) {
        float l = centre_pixel[-row_stride - C + c], h = l;  // from k = 0, as the fit reads the window
        for (int k = 1; k < window; ++k) {
          const float v = centre_pixel[(k / 3 - 1) * row_stride + (k % 3 - 1) * C + c];
          l = std::min(l, v);
          h = std::max(h, v);
        }
        lo[c] = l;
        hi[c] = h;
      }
      for (int c = 0; c < C; ++c)
        if (hi[c] - lo[c] >= main_step) main = c, main_step = hi[c] - lo[c], lo_main = lo[c], hi_main = hi[c];
      if (main < 0) continue;
      const double centre = window_value(4, main);
      const double margin = 1e-3 * main_step;
      if (!(centre > lo_main + margin && centre < hi_main - margin)) continue;
      // A straight line crosses at most 5 of the 3x3 pixels: the other 4 or
      // more sit on one of the two levels.
      int on_level = 0;
      const double allowed = options.tolerance * main_step + rounding;  // misfit of a 3x3 pixel
      const double near = 2 * allowed;
      for (int k = 0; k < window; ++k) {
        const double value = window_value(k, main);
        on_level += value <= lo_main + near || value >= hi_main - near;
      }
      if (on_level < 4) continue;
      const double reach = allowed + options.reach_tolerance * main_step + rounding + 1e-6 * main_step;
      if (!within_reach(src, top, x, y, lo, hi, reach)) continue;
      for (int k = 0; k < window; ++k) {
        w.cx[k] = x + k % 3 - 1 + 0.5;
        w.cy[k] = y + k / 3 - 1 + 0.5;
        for (int c = 0; c < C; ++c) w.value[k * C + c] = window_value(k, c);
      }
      const EdgeFit fit = fit_edge(w, main, lo_main, hi_main, allowed);
      if (!(fit.misfit <= allowed)) continue;
      bool levels_inside = true;  // no level beyond what the window shows
      for (int c = 0; c < C; ++c) {
        const double slack = allowed;
        levels_inside = levels_inside && std::min(fit.a[c], fit.b[c]) >= lo[c] - slack &&
                        std::max(fit.a[c], fit.b[c]) <= hi[c] + slack;
      }
      if (!levels_inside || !(misfit_5x5(src, top, x, y, fit) <= options.reach_tolerance * main_step + rounding)) continue;
      const double nx = std::cos(fit.angle), ny = std::sin(fit.angle);
      const double p = pw * std::abs(nx), q = ph * std::abs(ny);
      for (int c = 0; c < C; ++c) {
        o.clear();
        double mean = 0;
        for (int Y = f.first_y[y]; Y < f.first_y[y + 1]; ++Y)
          for (int X = f.first_x[x]; X < f.first_x[x + 1]; ++X) {
            mean += out.at(X, Y - out_origin, c);
            const double s = nx * (X + 0.5) * pw + ny * (Y + 0.5) * ph - fit.offset;
            o.push_back(static_cast<float>(fit.a[c] + (fit.b[c] - fit.a[c]) * rectangle_coverage(s, p, q)));
          }
        if (o.empty()) continue;
        mean = std::clamp(mean / o.size(), lo[c], hi[c]);
        const double t = mean_keeping_shift(o, mean, lo[c], hi[c]);
        std::size_t i = 0;
        for (int Y = f.first_y[y]; Y < f.first_y[y + 1]; ++Y)
          for (int X = f.first_x[x]; X < f.first_x[x + 1]; ++X)
            out.at(X, Y - out_origin, c) = static_cast<float>(std::clamp(o[i++] + t, lo[c], hi[c]));
      }
      ++drawn;
    }
  });
  return drawn;
}

}  // namespace ddt
