#include "image/cubic_surface.hpp"

#include "core/scan_convert.hpp"
#include "util/error.hpp"
#include "pipeline/upscale.hpp"

#include <tbb/parallel_for.h>

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

std::vector<float> grid_slopes(const float* values, const std::vector<int>& size, int channels,
                               SlopeLimiter limiter) {
  const int D = static_cast<int>(size.size());
  std::vector<std::size_t> stride(D);
  std::size_t n = 1;
  for (int axis = 0; axis < D; ++axis) stride[axis] = n, n *= static_cast<std::size_t>(size[axis]);
  std::vector<float> g(n * channels * D, 0.0f);
  if (n == 0) return g;
  const std::size_t per_slice = n / size[D - 1];
  tbb::parallel_for(0, size[D - 1], [&](int slice) {
    for (std::size_t i = slice * per_slice; i < (slice + 1) * per_slice; ++i)
      for (int axis = 0; axis < D; ++axis) {
        const int at = static_cast<int>(i / stride[axis] % size[axis]);
        bool has[5];
        for (int k = -2; k <= 2; ++k) has[k + 2] = at + k >= 0 && at + k < size[axis];
        for (int c = 0; c < channels; ++c) {
          double z[5];
          for (int k = -2; k <= 2; ++k)
            z[k + 2] = has[k + 2] ? values[(static_cast<std::ptrdiff_t>(i) + k * static_cast<std::ptrdiff_t>(stride[axis])) *
                                               channels + c]
                                  : 0.0;
          g[(i * channels + c) * D + axis] = static_cast<float>(limited_slope(z, has, limiter));
        }
      }
  });
  return g;
}

std::vector<float> grid_gradients(const Image& src, SlopeLimiter limiter) {
  return grid_slopes(src.pixels.data(), {src.width, src.height}, src.channels, limiter);
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
