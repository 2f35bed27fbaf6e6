#pragma once
// What a triangle paints: the plane through its vertex values (linear) or
// its cubic Bézier patch (Bernstein or power form), at pixel centres; and
// the exact edge test the walk and the shapes share.

#include "image/raster/scene.hpp"
#include "util/image.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace ddt::raster {

// Two doubles, one SSE2 register: element-wise IEEE operations.
typedef double v2d __attribute__((vector_size(16)));

// The cubic's Bernstein monomials at barycentric weights (l0, l1, l2), in
// the order of the control values (300, 030, 003, 210, 120, 021, 012, 102,
// 201, 111), without their multinomial factors; one order of operations
// everywhere (the same bits by any path). T: double or v2d.
template <class T>
void bernstein_monomials(T l0, T l1, T l2, T* m) {
  const T l00 = l0 * l0, l11 = l1 * l1, l22 = l2 * l2;
  m[0] = l00 * l0, m[1] = l11 * l1, m[2] = l22 * l2, m[3] = l00 * l1, m[4] = l0 * l11, m[5] = l11 * l2;
  m[6] = l1 * l22, m[7] = l0 * l22, m[8] = l00 * l2, m[9] = l0 * l1 * l2;
}

// One directed edge u->v of a triangle: inside is its left (side > 0).
struct Edge {
  Point2 u, v;
  double alpha, beta;  // v - u
  int tie;             // side on the line
  bool exact;          // plain double evaluation is exact
  // Side of pixel centre (X, Y): +1 or -1.
  int side(double X, double Y) const {
    const double l = alpha * (Y - u.y), r = beta * (X - u.x);
    const double e = l - r;
    if (exact) return e > 0 ? 1 : e < 0 ? -1 : tie;
    // Shewchuk's orient2d error bound, rounded up: beyond it the sign is
    // right; within, CGAL's exact predicate decides.
    if (std::abs(e) > 1e-15 * (std::abs(l) + std::abs(r))) return e > 0 ? 1 : -1;
    const int s = orientation(u, v, Point2{X, Y});
    return s != 0 ? s : tie;
  }
};

// The cubic's power form pays for its conversion from about 16 pixels a
// piece (docs/performance.md, "The cubic's power form"). Its terms can
// cancel where the Bernstein form's cannot. With K = (longest edge)^2 /
// (twice the area), |a X| + |b Y| <= K inside the triangle
// (Cauchy-Schwarz), so the terms of degree n sum to at most K^n |e_ij|, and
// |e_ij| <= 24 times the largest control value: in all at most about
// 64 K^3 times it. The rounding of the operations that combine them stays
// below about 1e-8 of it for K <= 20, below a float's ulp. Thinner
// triangles (rim slabs, needles) keep the Bernstein form.
constexpr int power_form_min_pixels = 16;
constexpr double power_form_max_shape = 20;

inline double max_edge2(const Point2& p0, const Point2& p1, const Point2& p2) {
  auto d2 = [](const Point2& u, const Point2& v) { return (v.x - u.x) * (v.x - u.x) + (v.y - u.y) * (v.y - u.y); };
  return std::max({d2(p0, p1), d2(p1, p2), d2(p2, p0)});
}

template <int C>
using channels = std::integral_constant<int, C>;  // 0: known at run time only

// What a triangle paints: the plane through its vertex values (linear) or
// its Bézier patch (cubic), evaluated at pixel centres.
template <int CT, bool cubic>
struct Shader {
  int C;
  Point2 p0;
  double inv_area2;  // 1 / (twice the signed area), in pixels
  bool add = false;  // linear: Scene::add
  // Linear: value = v0 + (X - p0.x) sx + (Y - p0.y) sy (exact at p0; the
  // other vertices are written exactly afterwards, see render_mesh).
  double v0[max_channels], sx[max_channels], sy[max_channels];
  // Cubic: Bézier control values, the middle ones pre-scaled by 3 and 6,
  // and the clamp to the vertex values (no overshoot, so no ringing beside
  // edges, whatever the gradients say).
  double b[cubic ? max_channels : 1][10], lo[cubic ? max_channels : 1], hi[cubic ? max_channels : 1];
  // Cubic, a mesh triangle's piece of many pixels: the same patch in
  // power form, a polynomial in (X, Y) = (x - p0.x, y - p0.y), so that
  // along a row it is a cubic in X (six operations a pixel instead of
  // twenty). Coefficients of X^3, X^2, X^2 Y, X, X Y, X Y^2, 1, Y, Y^2,
  // Y^3, by channel.
  bool by_power = false;
  double power[cubic ? max_channels : 1][10];

  // Set up when the triangle turns out to own a pixel (many own none at
  // small scales).
  void init(const Scene& scene, index_t t, const index_t id[3], const Point2& q0, const Point2& p1, const Point2& p2,
            double area2, long long pixels) {
    C = CT > 0 ? CT : scene.C, p0 = q0, inv_area2 = 1.0 / area2, add = scene.add;
    const float *z0 = scene.value(id[0]), *z1 = scene.value(id[1]), *z2 = scene.value(id[2]);
    const double ux = p1.x - p0.x, uy = p1.y - p0.y, vx = p2.x - p0.x, vy = p2.y - p0.y;
    if constexpr (cubic) {
      if (t < scene.T) {
        mesh_patches(scene, id);
        if (pixels >= power_form_min_pixels && max_edge2(p0, p1, p2) <= power_form_max_shape * area2) to_power(p1, p2);
        return;
      }
    }
    for (int c = 0; c < C; ++c) {
      const double dv1 = double(z1[c]) - z0[c], dv2 = double(z2[c]) - z0[c];
      if constexpr (!cubic) {
        v0[c] = z0[c];
        sx[c] = (dv1 * vy - dv2 * uy) * inv_area2;
        sy[c] = (dv2 * ux - dv1 * vx) * inv_area2;
      } else {
        const std::array<double, 10> patch = scene_patch(scene, t, id, c);
        for (int q = 0; q < 10; ++q) b[c][q] = patch[q] * (q < 3 ? 1.0 : q < 9 ? 3.0 : 6.0);
        lo[c] = std::min({double(z0[c]), double(z1[c]), double(z2[c])});
        hi[c] = std::max({double(z0[c]), double(z1[c]), double(z2[c])});
      }
    }
  }
  // Cubic, a mesh triangle: cubic_patch() of every channel, two channels
  // at a time (lane by lane the same operations in the same order, so the
  // same bits), pre-scaled and with the clamp range, as above.
  void mesh_patches(const Scene& scene, const index_t id[3]) {
    const Point2 &P0 = scene.mesh.points[id[0]], &P1 = scene.mesh.points[id[1]], &P2 = scene.mesh.points[id[2]];
    const float* Z[3] = {&scene.values[static_cast<std::size_t>(id[0]) * C], &scene.values[static_cast<std::size_t>(id[1]) * C],
                         &scene.values[static_cast<std::size_t>(id[2]) * C]};
    const float* G[3];
    for (int i = 0; i < 3; ++i) G[i] = scene.gradient(id[i]);
    const v2d three = {3.0, 3.0}, six = {6.0, 6.0}, half = {0.5, 0.5};
    // along(g, from, to) = (g.x (to.x - from.x) + g.y (to.y - from.y)) / 3
    const v2d d01x = v2d{P1.x - P0.x, P1.x - P0.x}, d01y = v2d{P1.y - P0.y, P1.y - P0.y};
    const v2d d10x = v2d{P0.x - P1.x, P0.x - P1.x}, d10y = v2d{P0.y - P1.y, P0.y - P1.y};
    const v2d d12x = v2d{P2.x - P1.x, P2.x - P1.x}, d12y = v2d{P2.y - P1.y, P2.y - P1.y};
    const v2d d21x = v2d{P1.x - P2.x, P1.x - P2.x}, d21y = v2d{P1.y - P2.y, P1.y - P2.y};
    const v2d d20x = v2d{P0.x - P2.x, P0.x - P2.x}, d20y = v2d{P0.y - P2.y, P0.y - P2.y};
    const v2d d02x = v2d{P2.x - P0.x, P2.x - P0.x}, d02y = v2d{P2.y - P0.y, P2.y - P0.y};
    for (int c = 0; c < C; c += 2) {
      const int c1 = c + 1 < C ? c + 1 : c;  // the last lane repeats an odd channel
      auto pair = [&](const float* a, int stride) { return v2d{double(a[c * stride]), double(a[c1 * stride])}; };
      const v2d z0 = pair(Z[0], 1), z1 = pair(Z[1], 1), z2 = pair(Z[2], 1);
      const v2d g0x = pair(G[0], 2), g0y = pair(G[0] + 1, 2), g1x = pair(G[1], 2), g1y = pair(G[1] + 1, 2),
                g2x = pair(G[2], 2), g2y = pair(G[2] + 1, 2);
      const v2d b3 = z0 + (g0x * d01x + g0y * d01y) / three;  // 210
      const v2d b4 = z1 + (g1x * d10x + g1y * d10y) / three;  // 120
      const v2d b5 = z1 + (g1x * d12x + g1y * d12y) / three;  // 021
      const v2d b6 = z2 + (g2x * d21x + g2y * d21y) / three;  // 012
      const v2d b7 = z2 + (g2x * d20x + g2y * d20y) / three;  // 102
      const v2d b8 = z0 + (g0x * d02x + g0y * d02y) / three;  // 201
      const v2d edge_mean = (b3 + b4 + b5 + b6 + b7 + b8) / six;
      const v2d vertex_mean = (z0 + z1 + z2) / three;
      const v2d b9 = edge_mean + half * (edge_mean - vertex_mean);
      const v2d q[10] = {z0, z1, z2, b3 * three, b4 * three, b5 * three, b6 * three, b7 * three, b8 * three, b9 * six};
      // std::min({z0, z1, z2}) and std::max: the first of equal values (signed zeros)
      const v2d mn0 = z1 < z0 ? z1 : z0, mx0 = z0 < z1 ? z1 : z0;
      const v2d mn = z2 < mn0 ? z2 : mn0, mx = mx0 < z2 ? z2 : mx0;
      for (int lane = 0; lane < (c1 > c ? 2 : 1); ++lane) {
        for (int k = 0; k < 10; ++k) b[c + lane][k] = q[k][lane];
        lo[c + lane] = mn[lane], hi[c + lane] = mx[lane];
      }
    }
  }
  // Bernstein to power form. In s = l1 = a X + b Y and t = l2 = c X + d Y
  // (both zero at p0; l0 = 1 - s - t) the patch is sum e_ij s^i t^j, with
  // e from the control values by a fixed integer matrix; each s^i t^j is
  // then expanded in X and Y.
  void to_power(const Point2& p1, const Point2& p2) {
    const double a = (p2.y - p0.y) * inv_area2, b_ = (p0.x - p2.x) * inv_area2;
    const double c_ = (p0.y - p1.y) * inv_area2, d = (p1.x - p0.x) * inv_area2;
    // Homogeneous products, coefficients of X^n, X^(n-1) Y, ..., Y^n.
    const double S2[3] = {a * a, 2 * a * b_, b_ * b_}, ST[3] = {a * c_, a * d + b_ * c_, b_ * d},
                 T2[3] = {c_ * c_, 2 * c_ * d, d * d};
    auto times = [](const double q[3], double u, double v, double out[4]) {  // q (u X + v Y)
      out[0] = u * q[0], out[1] = u * q[1] + v * q[0], out[2] = u * q[2] + v * q[1], out[3] = v * q[2];
    };
    double S3[4], S2T[4], ST2[4], T3[4];
    times(S2, a, b_, S3), times(S2, c_, d, S2T), times(T2, a, b_, ST2), times(T2, c_, d, T3);
    for (int c = 0; c < C; ++c) {
      const double* q = b[c];  // pre-scaled: 300, 030, 003, 3 x (210, 120, 021, 012, 102, 201), 6 x 111
      const double e01 = -3 * q[0] + q[8], e02 = 3 * q[0] + q[7] - 2 * q[8], e03 = -q[0] + q[2] - q[7] + q[8];
      const double e10 = -3 * q[0] + q[3], e11 = 6 * q[0] - 2 * q[3] - 2 * q[8] + q[9];
      const double e12 = -3 * q[0] + q[3] + q[6] - q[7] + 2 * q[8] - q[9];
      const double e20 = 3 * q[0] - 2 * q[3] + q[4], e21 = -3 * q[0] + 2 * q[3] - q[4] + q[5] + q[8] - q[9];
      const double e30 = -q[0] + q[1] + q[3] - q[4];
      double cubic_terms[4];
      for (int k = 0; k < 4; ++k) cubic_terms[k] = e30 * S3[k] + e21 * S2T[k] + e12 * ST2[k] + e03 * T3[k];
      double* w = power[c];
      w[0] = cubic_terms[0], w[2] = cubic_terms[1], w[5] = cubic_terms[2], w[9] = cubic_terms[3];
      w[1] = e20 * S2[0] + e11 * ST[0] + e02 * T2[0];
      w[4] = e20 * S2[1] + e11 * ST[1] + e02 * T2[1];
      w[8] = e20 * S2[2] + e11 * ST[2] + e02 * T2[2];
      w[3] = e10 * a + e01 * c_, w[7] = e10 * b_ + e01 * d;
      w[6] = q[0];
    }
    by_power = true;
  }
  // Cubic by the power form: pixels xs..xe of row y, two at a time.
  void power_row(int y, int xs, int xe, float* px) const {
    const double Y = y - p0.y;
    // The row's cubic in X by channel, in both lanes.
    v2d a0[max_channels], a1[max_channels], a2[max_channels], a3[max_channels];
    for (int c = 0; c < C; ++c) {
      const double* w = power[c];
      const double k2 = w[1] + w[2] * Y, k1 = w[3] + (w[4] + w[5] * Y) * Y, k0 = w[6] + (w[7] + (w[8] + w[9] * Y) * Y) * Y;
      a3[c] = v2d{w[0], w[0]}, a2[c] = v2d{k2, k2}, a1[c] = v2d{k1, k1}, a0[c] = v2d{k0, k0};
    }
    // Pixels x and x + 1 at `at`; an odd last pixel is a pair's first lane.
    auto pixels = [&](int x, float* at, bool both) {
      const v2d X = v2d{double(x), double(x + 1)} - p0.x;
      for (int c = 0; c < C; ++c) {
        const v2d r = clamp_pair(((a3[c] * X + a2[c]) * X + a1[c]) * X + a0[c], c);
        at[c] = static_cast<float>(r[0]);
        if (both) at[C + c] = static_cast<float>(r[1]);
      }
    };
    int x = xs;
    for (; x < xe; x += 2, px += 2 * C) pixels(x, px, true);
    if (x == xe) pixels(x, px, false);
  }
  // std::clamp(v, lo[c], hi[c]) in both lanes (v < lo ? lo : hi < v ? hi : v),
  // as pixel() does it.
  v2d clamp_pair(v2d v, int c) const {
    const v2d vlo = {lo[c], lo[c]}, vhi = {hi[c], hi[c]};
    const v2d r1 = v < vlo ? vlo : v;
    return vhi < r1 ? vhi : r1;
  }
  // Linear: pixels xs..xe of row Y.
  void row(double Y, int xs, int xe, float* px) const {
    double base[max_channels];
    for (int c = 0; c < C; ++c) base[c] = v0[c] + (Y - p0.y) * sy[c] + (xs - p0.x) * sx[c];
    for (int x = xs; x <= xe; ++x, px += C) {
      const double dx = x - xs;
      for (int c = 0; c < C; ++c) put(px[c], static_cast<float>(base[c] + dx * sx[c]));
    }
  }
  // Linear: one pixel as row() draws it, from dy = Y - p0.y, dxs = xs - p0.x
  // and dx = x - xs (the same operations in the same order).
  void placed_pixel(double dy, double dxs, double dx, float* px) const {
    for (int c = 0; c < C; ++c) put(px[c], static_cast<float>((v0[c] + dy * sy[c] + dxs * sx[c]) + dx * sx[c]));
  }
  // Linear: a pixel's value written, or added to the pixel's own.
  void put(float& pixel, float value) const { pixel = add ? pixel + value : value; }
  // Cubic: one pixel from its barycentric weights.
  void pixel(double l0, double l1, double l2, float* px) const {
    double m[10];
    bernstein_monomials(l0, l1, l2, m);
    monomial_pixel(m, px);
  }
  // Cubic: one pixel from its monomials m (pixel()'s), clamped.
  void monomial_pixel(const double* m, float* px) const {
    for (int c = 0; c < C; ++c) {
      const double* bc = b[c];
      // A balanced sum: short dependency chains.
      const double v = ((bc[0] * m[0] + bc[1] * m[1]) + (bc[2] * m[2] + bc[3] * m[3])) +
                       ((bc[4] * m[4] + bc[5] * m[5]) + (bc[6] * m[6] + bc[7] * m[7])) + (bc[8] * m[8] + bc[9] * m[9]);
      px[c] = static_cast<float>(std::clamp(v, lo[c], hi[c]));
    }
  }
  // Cubic: two pixels at once (at px and qx), lane by lane the same
  // operations in the same order as pixel(), so the same bits.
  void pixel_pair(v2d l0, v2d l1, v2d l2, float* px, float* qx) const {
    v2d m[10];
    bernstein_monomials(l0, l1, l2, m);
    monomial_pair(m, px, qx);
  }
  // Cubic: two pixels from their monomials, lane by lane as monomial_pixel().
  void monomial_pair(const v2d* m, float* px, float* qx) const {
    for (int c = 0; c < C; ++c) {
      const double* bc = b[c];
      const v2d v = ((bc[0] * m[0] + bc[1] * m[1]) + (bc[2] * m[2] + bc[3] * m[3])) +
                    ((bc[4] * m[4] + bc[5] * m[5]) + (bc[6] * m[6] + bc[7] * m[7])) + (bc[8] * m[8] + bc[9] * m[9]);
      const v2d r = clamp_pair(v, c);
      px[c] = static_cast<float>(r[0]);
      qx[c] = static_cast<float>(r[1]);
    }
  }
};

}  // namespace ddt::raster
