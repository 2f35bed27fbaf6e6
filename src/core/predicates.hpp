#pragma once
// ddt::core predicates — exact geometric signs for any dimension D, through
// CGAL's filtered exact kernels (Epick for D = 2, 3; Epick_d<Dimension_tag<D>>
// for D = 4; D = 1 is a comparison). Each returns -1, 0 or +1 and is exact
// for all finite double inputs (a floating-point filter first, exact
// arithmetic only when the filter cannot decide).
//
// Sign conventions (CGAL's, written once here)
//   orient<D>(p0, ..., pD) = sign det[p1 - p0, ..., pD - p0] (rows).
//     2D: +1 when p0 p1 p2 turn counter-clockwise.
//     3D: +1 when p3 lies on the side of plane p0 p1 p2 from which p0 p1 p2
//         are seen counter-clockwise (the unit simplex 0, e1, e2, e3 is +1).
//     Swapping two points flips the sign; 0 iff affinely dependent.
//   in_sphere<D>(p0, ..., pD; q) = +1 when q lies strictly inside the
//     circumsphere of the simplex, 0 on it, -1 outside. Independent of the
//     simplex's orientation. Precondition: orient<D>(p) != 0.
//   perturbed_orient<D>(p0, ..., pD) = orient<D> with pD moved to
//     pD + (e, e^2, ..., e^D) for an infinitesimal e > 0: the one symbolic
//     tie-break (Edelsbrunner & Muecke's simulation of simplicity restricted
//     to the query point). Nonzero whenever p0 .. p(D-1) are affinely
//     independent, and antisymmetric in them, so of two cells sharing a
//     facet exactly one owns a point that lies on it. The 2D rasterizer's
//     pixel ownership and scan_convert<D>'s sample ownership use it.
//   perturbed_tie<D>(p0, ..., p(D-1)) = what perturbed_orient returns when
//     orient is 0: the sign of the perturbation term, which depends on the
//     facet only (so a rasterizer computes it once per edge or face).
//   radon_partition<D>(s0, ..., s(D+1)): the signs of the affine dependence
//     sum l_i s_i = 0, sum l_i = 0, of D + 2 points, l_i = (-1)^i
//     orient<D>(S \ s_i) (Cramer's rule). A = {i : l_i > 0} and B = {i :
//     l_i < 0} are Radon's partition (conv A meets conv B); i with l_i = 0
//     are the points outside the circuit. The overall sign is arbitrary
//     (A and B may be exchanged). Precondition: the points span R^D (then
//     the dependence is unique up to scale).

#include "core/simplex_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace ddt::core {

template <int D>
int orient(const std::array<Vec<D>, D + 1>& p);

template <int D>
int in_sphere(const std::array<Vec<D>, D + 1>& simplex, const Vec<D>& q);

template <int D>
int perturbed_orient(const std::array<Vec<D>, D + 1>& p);

// orient is linear in the last point q = pD: det = sum_k c_k (q_k - p0_k),
// with c_k the cofactor of the last row. Moving q by (e, e^2, ..., e^D)
// adds sum_k c_k e^k, so on a tie the first nonzero c_k decides. c_k is, up
// to the sign (-1)^(D+k) (k from 1), the (D-1)-dimensional orientation of
// p0 .. p(D-1) with coordinate k dropped: exact through orient<D-1> (a
// comparison for D = 2, written out so the rasterizer's edges inline it).
template <int D>
int perturbed_tie(const std::array<Vec<D>, D>& facet) {
  if constexpr (D == 1) {
    return 1;  // q + e lies to the right of p0
  } else {
    for (int k = 0; k < D; ++k) {
      std::array<Vec<D - 1>, D> projected;
      for (int i = 0; i < D; ++i)
        for (int j = 0, n = 0; j < D; ++j)
          if (j != k) projected[i][n++] = facet[i][j];
      int minor;
      if constexpr (D == 2)
        minor = (projected[1][0] > projected[0][0]) - (projected[1][0] < projected[0][0]);
      else
        minor = orient<D - 1>(projected);
      if (minor != 0) return ((D + k + 1) % 2 == 0) ? minor : -minor;
    }
    return 0;  // p0 .. p(D-1) are affinely dependent
  }
}

template <int D>
std::array<int, D + 2> radon_partition(const std::array<Vec<D>, D + 2>& s);

// The lattice precondition, the one fast path of the core's predicates:
// every coordinate is finite and an integer multiple of 2^-s (s <= 30), and
// with u = 2 max|coordinate| * 2^s (the largest coordinate difference in
// units of 2^-s), D! u^D <= 2^53. Then every intermediate of the cofactor
// expansion of det[p1 - p0, ..., pD - p0] is an integer multiple of 2^-Ds
// below 2^53 in magnitude, so plain double arithmetic computes it exactly.
// Voxel and pixel centres ((i + 0.5) for i < 2^14 in 3D) satisfy it.
// O(V D).
template <int D>
bool lattice_exact(const std::vector<Vec<D>>& points);

// lattice_exact for any container of points; coordinate(p, k) reads
// coordinate k of point p (the 2D mesh's Point2 has x and y).
template <int D, class Points, class Coordinate>
bool lattice_exact(const Points& points, Coordinate coordinate) {
  double largest = 0;
  int s = 0;
  for (const auto& p : points)
    for (int k = 0; k < D; ++k) {
      const double c = coordinate(p, k);
      if (!std::isfinite(c)) return false;
      largest = std::max(largest, std::abs(c));
      while (std::ldexp(c, s) != std::floor(std::ldexp(c, s)))
        if (++s > 30) return false;
    }
  double bound = std::pow(std::ldexp(2 * largest, s), D);
  for (int k = 2; k <= D; ++k) bound *= k;
  return bound <= 9007199254740992.0;  // 2^53
}

// The rasterizer's lattice (image/raster): c is an integer multiple of
// 2^-fraction_bits below bound in magnitude, checked by one exact
// conversion (bound * 2^fraction_bits <= 2^53).
inline bool on_lattice(double c, int fraction_bits, double bound) {
  const double scaled = c * std::ldexp(1.0, fraction_bits);  // exact: a power of two
  return std::abs(c) < bound && scaled == static_cast<double>(static_cast<long long>(scaled));
}

// det[p1 - p0, ..., pD - p0] by cofactor expansion in plain double (D <=
// 4): the exact determinant when the points satisfy lattice_exact (so the
// same number as any other exact evaluation, e.g. simplex_content's),
// meaningless otherwise.
template <int D>
[[gnu::always_inline]] inline double lattice_det(const std::array<Vec<D>, D + 1>& p) {
  static_assert(D >= 1 && D <= 4, "lattice_det is written out for D <= 4");
  std::array<std::array<double, D>, D> m;
  for (int r = 0; r < D; ++r)
    for (int k = 0; k < D; ++k) m[r][k] = p[r + 1][k] - p[0][k];
  auto det2 = [&](int r0, int r1, int c0, int c1) { return m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]; };
  auto det3 = [&](int r0, int r1, int r2, int c0, int c1, int c2) {
    return m[r0][c0] * det2(r1, r2, c1, c2) - m[r0][c1] * det2(r1, r2, c0, c2) + m[r0][c2] * det2(r1, r2, c0, c1);
  };
  double det = 0;
  if constexpr (D == 1) det = m[0][0];
  if constexpr (D == 2) det = det2(0, 1, 0, 1);
  if constexpr (D == 3) det = det3(0, 1, 2, 0, 1, 2);
  if constexpr (D == 4)
    det = m[0][0] * det3(1, 2, 3, 1, 2, 3) - m[0][1] * det3(1, 2, 3, 0, 2, 3) + m[0][2] * det3(1, 2, 3, 0, 1, 3) -
          m[0][3] * det3(1, 2, 3, 0, 1, 2);
  return det;
}

// orient<D> from lattice_det: equal to orient<D> when the points satisfy
// lattice_exact (tested). Inlined: the optimizer calls it for nearly every
// test.
template <int D>
[[gnu::always_inline]] inline int orient_lattice(const std::array<Vec<D>, D + 1>& p) {
  const double det = lattice_det<D>(p);
  return (det > 0) - (det < 0);
}

// orient<D>, or orient_lattice<D> when the caller knows lattice_exact holds.
template <int D>
[[gnu::always_inline]] inline int orient(const std::array<Vec<D>, D + 1>& p, bool lattice) {
  return lattice ? orient_lattice<D>(p) : orient<D>(p);
}

// orient<D> of the cell with vertex ids v in `points`.
template <int D>
int orient_ids(const std::vector<Vec<D>>& points, const CellVertices<D>& v, bool lattice = false) {
  std::array<Vec<D>, D + 1> p;
  for (int i = 0; i <= D; ++i) p[i] = points[v[i]];
  return orient<D>(p, lattice);
}

}  // namespace ddt::core
