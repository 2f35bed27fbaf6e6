#pragma once
// ddt::core::delaunay<D> — the Delaunay triangulation of points in R^D as a
// SimplexMesh<D>, built by CGAL (Delaunay_triangulation_2 / _3 with the Epick
// kernel, Delaunay_triangulation with Epick_d<Dimension_tag<4>> for D = 4)
// and handed over as flat arrays.
//
// Inputs:
//   points  #V distinct positions, any order
// Outputs:
//   SimplexMesh<D> over `points` (vertex ids are indices into it), with no
//   free slots. Canonical cell order: each cell's ids sorted ascending, the
//   last two swapped when that order is negatively oriented, and the cells
//   sorted by these tuples; facets glued by link_facets. Points not in
//   general position (a grid's cospherical cells) get CGAL's choice, a
//   valid Delaunay triangulation. Fewer than D + 1 affinely independent
//   points give a mesh without cells.
// Precondition: the points are distinct (a repeated position would leave
// one of its ids unreferenced, chosen by CGAL).
// Complexity: O(V log V) expected for D = 2, 3; CGAL's dD incremental
// insertion for D = 4 (meant for tests and small inputs).

#include "core/simplex_mesh.hpp"

#include <vector>

namespace ddt::core {

template <int D>
SimplexMesh<D> delaunay(const std::vector<Vec<D>>& points);

}  // namespace ddt::core
