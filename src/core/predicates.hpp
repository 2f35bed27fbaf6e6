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
//     facet exactly one owns a point that lies on it. For D = 2 it is
//     rasterizer.cpp's tie_side.
//   radon_partition<D>(s0, ..., s(D+1)): the signs of the affine dependence
//     sum l_i s_i = 0, sum l_i = 0, of D + 2 points, l_i = (-1)^i
//     orient<D>(S \ s_i) (Cramer's rule). A = {i : l_i > 0} and B = {i :
//     l_i < 0} are Radon's partition (conv A meets conv B); i with l_i = 0
//     are the points outside the circuit. The overall sign is arbitrary
//     (A and B may be exchanged). Precondition: the points span R^D (then
//     the dependence is unique up to scale).

#include "core/simplex_mesh.hpp"

#include <array>

namespace ddt::core {

template <int D>
int orient(const std::array<Vec<D>, D + 1>& p);

template <int D>
int in_sphere(const std::array<Vec<D>, D + 1>& simplex, const Vec<D>& q);

template <int D>
int perturbed_orient(const std::array<Vec<D>, D + 1>& p);

template <int D>
std::array<int, D + 2> radon_partition(const std::array<Vec<D>, D + 2>& s);

// orient<D> of the cell with vertex ids v in `points`.
template <int D>
int orient_ids(const std::vector<Vec<D>>& points, const CellVertices<D>& v) {
  std::array<Vec<D>, D + 1> p;
  for (int i = 0; i <= D; ++i) p[i] = points[v[i]];
  return orient<D>(p);
}

}  // namespace ddt::core
