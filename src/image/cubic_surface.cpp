#include "image/cubic_surface.hpp"

#include "core/scan_convert.hpp"
#include "util/error.hpp"
#include "pipeline/upscale.hpp"

#include <algorithm>
#include <cmath>

namespace ddt {
namespace {

double minmod(double a, double b) {
  if (a * b <= 0) return 0;
  return std::abs(a) < std::abs(b) ? a : b;
}

}  // namespace

double limited_slope(const double z[5], const bool has[5], SlopeLimiter limiter) {
  if (!has[1] && !has[3]) return 0;
  if (!has[1]) return z[3] - z[2];
  if (!has[3]) return z[2] - z[1];
  const double dm = z[2] - z[1], dp = z[3] - z[2];
  const double central = 0.5 * (dm + dp);
  switch (limiter) {
    case SlopeLimiter::central: return central;
    case SlopeLimiter::minmod: return minmod(dm, dp);
    case SlopeLimiter::mc: return minmod(minmod(2 * dm, 2 * dp), central);
    case SlopeLimiter::mc4: {
      const double fourth = has[0] && has[4] ? (z[0] - 8 * z[1] + 8 * z[3] - z[4]) / 12.0 : central;
      return minmod(minmod(2 * dm, 2 * dp), fourth);
    }
  }
  return 0;
}

std::vector<float> grid_gradients(const Image& src, SlopeLimiter limiter) {
  const int W = src.width, H = src.height, C = src.channels;
  std::vector<float> g(src.pixel_count() * C * 2, 0.0f);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < C; ++c) {
        double zx[5], zy[5];
        bool hx[5], hy[5];
        for (int k = -2; k <= 2; ++k) {
          hx[k + 2] = x + k >= 0 && x + k < W;
          hy[k + 2] = y + k >= 0 && y + k < H;
          zx[k + 2] = hx[k + 2] ? src.at(x + k, y, c) : 0.0;
          zy[k + 2] = hy[k + 2] ? src.at(x, y + k, c) : 0.0;
        }
        float* out = &g[(src.index(x, y, c)) * 2];
        out[0] = static_cast<float>(limited_slope(zx, hx, limiter));
        out[1] = static_cast<float>(limited_slope(zy, hy, limiter));
      }
  return g;
}

std::array<double, 10> cubic_patch(const Point2& p0, const Point2& p1, const Point2& p2, double z0, double z1,
                                   double z2, const double g0[2], const double g1[2], const double g2[2]) {
  // The core's D-dimensional patch (the same arithmetic), in this order.
  const std::array<core::Vec<2>, 3> p = {{{p0.x, p0.y}, {p1.x, p1.y}, {p2.x, p2.y}}};
  const double z[3] = {z0, z1, z2}, g[6] = {g0[0], g0[1], g1[0], g1[1], g2[0], g2[1]};
  double c[core::cubic_controls<2>];
  core::cubic_patch<2>(p, z, g, c);
  using core::pair_control;
  return {c[0], c[1], c[2], c[pair_control<2>(0, 1)], c[pair_control<2>(1, 0)], c[pair_control<2>(1, 2)],
          c[pair_control<2>(2, 1)], c[pair_control<2>(2, 0)], c[pair_control<2>(0, 2)], c[9]};
}

}  // namespace ddt
