#pragma once
// ddt::core::cubic_patch<D> — the cubic render's patch on one D-simplex
// (core/scan_convert.hpp draws it; image/cubic_surface.hpp is its 2D form).

#include "core/simplex_mesh.hpp"

#include <array>

namespace ddt::core {

// The cubic Bézier triangle of image/cubic_surface.hpp in D dimensions.
// Control values: at vertex i its value z_i; at the ordered pair (i, j)
// (two thirds of the way from p_j to p_i) z_i + g_i . (p_j - p_i) / 3; at each triple i < j < k the
// triangle's quadratic-precision rule E + (E - V) / 2, E the mean of its
// six pair values, V of its three vertex values. Every control value of a
// face depends on that face's vertices alone, so neighbouring patches meet
// continuously; linear and quadratic fields are reproduced when the
// gradients are exact. Layout: vertices, then pair (i, j) at
// pair_control(i, j), then the triples in lexicographic order.
template <int D>
inline constexpr int cubic_controls = (D + 1) + (D + 1) * D + (D + 1) * D * (D - 1) / 6;
template <int D>
constexpr int pair_control(int i, int j) {
  return (D + 1) + i * D + (j < i ? j : j - 1);
}
// z: the D + 1 vertex values; g: their gradients, D each; b: cubic_controls<D> values.
template <int D>
void cubic_patch(const std::array<Vec<D>, D + 1>& p, const double* z, const double* g, double* b);
// The patch's value at barycentric coordinates w (D + 1 of them).
template <int D>
double eval_cubic(const double* b, const double* w);

}  // namespace ddt::core
