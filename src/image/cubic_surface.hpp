#pragma once
// A smooth surface on the DDT mesh: one cubic Bézier triangle per triangle,
// built from the values and gradients at its three vertices (the scalar form
// of the PN-triangle / Farin construction). Along an edge the cubic depends
// only on the edge's two end values and their gradients along the edge, so
// neighbouring patches meet continuously (C0 everywhere, C1 where the vertex
// gradients agree, which is everywhere in smooth regions). Linear functions
// are reproduced exactly when the gradients are exact, quadratics too (the
// centre control point follows the quadratic-precision rule).
//
// Gradients come from the pixel grid with a slope limiter per axis, so the
// surface is smooth like bicubic where the image is smooth and does not ring
// at edges, where the DDT mesh already runs along the edge:
//   central     (z[+1] - z[-1]) / 2                 (Catmull-Rom's slopes)
//   mc          monotonized central: minmod(2 d-, (d- + d+) / 2, 2 d+)
//   minmod      minmod(d-, d+)
//   mc4         (default) minmod(2 d-, s4, 2 d+), s4 the fourth-order central
//               difference (central where the stencil leaves the image)
// with d- = z[0] - z[-1], d+ = z[+1] - z[0] (one-sided at the border).

#include "ddtscale/options.hpp"
#include "util/image.hpp"
#include "image/mesh.hpp"

#include <array>
#include <string>
#include <vector>

namespace ddt {

// The limited slope at z[2] of five samples z[-2..2] along one axis;
// has[k]: whether z[k] exists (the grid's border).
double limited_slope(const double z[5], const bool has[5], SlopeLimiter limiter);

// The limited slope of every sample of a grid (any number of axes, axis 0
// fastest; `channels` values per sample) along each axis: #samples by
// channels by #axes floats, spacing 1 (images: grid_gradients; volumes'
// cubic render).
std::vector<float> grid_slopes(const float* values, const std::vector<int>& size, int channels,
                               SlopeLimiter limiter);

// Per-pixel gradients of every channel: #pixels by C by 2 (d/dx, d/dy), row-major.
std::vector<float> grid_gradients(const Image& src, SlopeLimiter limiter);

// The ten control values b[i][j][k] (i + j + k = 3) in the order
// 300, 030, 003, 210, 120, 021, 012, 102, 201, 111.
std::array<double, 10> cubic_patch(const Point2& p0, const Point2& p1, const Point2& p2, double z0, double z1,
                                   double z2, const double g0[2], const double g1[2], const double g2[2]);

// Value of the patch at barycentric coordinates (l0, l1, l2).
inline double eval_cubic_patch(const std::array<double, 10>& b, double l0, double l1, double l2) {
  return b[0] * l0 * l0 * l0 + b[1] * l1 * l1 * l1 + b[2] * l2 * l2 * l2 +
         3 * (b[3] * l0 * l0 * l1 + b[4] * l0 * l1 * l1 + b[5] * l1 * l1 * l2 + b[6] * l1 * l2 * l2 +
              b[7] * l0 * l2 * l2 + b[8] * l0 * l0 * l2) +
         6 * b[9] * l0 * l1 * l2;
}

}  // namespace ddt
