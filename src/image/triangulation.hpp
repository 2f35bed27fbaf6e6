#pragma once
// ddt::delaunay_triangulation — the initial mesh: the 2D Delaunay
// triangulation of arbitrary points, built by CGAL (exact predicates) and
// handed over as flat arrays. Points that form a pixel grid (a row-major
// lattice of unit spacing) take the core's repeated cell instead
// (core/grid_delaunay.hpp): the same arrays, in O(n).
//
// Inputs:
//   points  #V positions; any order, not all collinear for a 2D result
// Outputs:
//   Mesh2 whose vertex ids are indices into `points`. Triangles are sorted
//   by their vertex ids (each listed from its smallest id, counter-clockwise),
//   so the result is independent of the order CGAL inserted the points.
//   Fewer than 3 non-collinear points give a mesh with no triangles.
//   Repeated positions: the smallest id at a position is used, the others
//   stay unreferenced.
//
// Ties: where four or more points are cocircular (every 2x2 block of a pixel
// grid) Delaunay is ambiguous. We resolve it by symbolic perturbation of the
// parabolic lifting (Edelsbrunner & Mücke's simulation of simplicity): the
// point with the smallest id is lifted by an infinitesimal that dominates all
// others. That lifting is generic, so Lawson flips under it terminate in the
// unique regular triangulation, whatever CGAL returned.
// Complexity: O(V log V) expected.

#include "image/mesh.hpp"

#include <vector>

namespace ddt {

Mesh2 delaunay_triangulation(const std::vector<Point2>& points);
// The same, the points moved into the mesh (a pixel grid's: no copy of them held beside it).
Mesh2 delaunay_triangulation(std::vector<Point2>&& points);

// In-circle test with the tie-break above: true when the edge of half-edge e
// must be flipped to make the mesh the perturbed Delaunay triangulation.
bool violates_perturbed_delaunay(const Mesh2& mesh, index_t e);

// core::is_delaunay<2> of as_simplex_mesh(mesh): no point of an adjacent
// triangle strictly inside a triangle's circumcircle (exact), on every
// interior edge (local Delaunay everywhere implies global Delaunay).
bool is_delaunay(const Mesh2& mesh);

}  // namespace ddt
