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

// Points in layers (layer_size consecutive points each, every layer in a
// plane of its own, the planes parallel and in order: the frames of an
// image sequence, sheared or not): the Delaunay triangulation of each two
// consecutive layers, canonical as above, glued along the layers they
// share; cells in slab order (the canonical order, since ids grow with
// the layer). Each slab is triangulated alone (in parallel, its CGAL
// triangulation freed before the next), so memory and time stay those of
// two layers, and a slab's cells depend on its two layers only. Returns
// false, leaving mesh as it was, when a shared layer is triangulated
// differently from its two sides (not seen; the caller then takes
// delaunay<3> of all the points) or when there are fewer than two layers.
// Errors: throws ddt::Error when the facet ids would overflow index_t.
bool layered_delaunay(const std::vector<Vec<3>>& points, index_t layer_size, SimplexMesh<3>& mesh);

}  // namespace ddt::core
