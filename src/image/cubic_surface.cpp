#include "image/cubic_surface.hpp"

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
  auto along = [](const double g[2], const Point2& from, const Point2& to) {
    return (g[0] * (to.x - from.x) + g[1] * (to.y - from.y)) / 3.0;
  };
  std::array<double, 10> b;
  b[0] = z0, b[1] = z1, b[2] = z2;
  b[3] = z0 + along(g0, p0, p1);  // 210
  b[4] = z1 + along(g1, p1, p0);  // 120
  b[5] = z1 + along(g1, p1, p2);  // 021
  b[6] = z2 + along(g2, p2, p1);  // 012
  b[7] = z2 + along(g2, p2, p0);  // 102
  b[8] = z0 + along(g0, p0, p2);  // 201
  const double edge_mean = (b[3] + b[4] + b[5] + b[6] + b[7] + b[8]) / 6.0;
  const double vertex_mean = (z0 + z1 + z2) / 3.0;
  b[9] = edge_mean + 0.5 * (edge_mean - vertex_mean);
  return b;
}

}  // namespace ddt
