#pragma once
// ddt::core::grid_delaunay<D> — the Delaunay triangulation of the sample
// centres of a D-dimensional grid, as core::delaunay<D> (CGAL) gives it,
// built in O(n) from one cell repeated (D = 3: the initial mesh of a volume,
// D = 4: of a volume series).
//
// The Delaunay cells of a grid are its cubes (the 2^D corners of a cube are
// cospherical, every other point lies outside their sphere). CGAL resolves
// the ties by symbolic perturbation (Devillers & Teillaud, SODA 2003; the dD
// triangulation likewise): points ordered lexicographically, lifted by
// infinitesimals in that order. That refines each cube by the order of its
// corners, the same in every cube (a translation keeps the order). So CGAL
// triangulates one cube, and its pattern is repeated in
// core::delaunay's canonical order (each cell's ids ascending, the last two
// swapped for a positive orientation; cells sorted). The corner offsets grow
// with the corner number, so a translated cell keeps the pattern's order and
// orientation. Tests check the arrays equal core::delaunay<D>'s for D = 3, 4.
//
// Inputs: size, the samples per axis (axis 0 fastest, as Volume::index);
//   point (i0, ..., i(D-1)) sits at (i0 + 0.5, ..., i(D-1) + 0.5) and has id
//   i0 + size[0] (i1 + size[1] (...)).
// Output: SimplexMesh<D> without free slots. A grid with a side of 1 falls
//   back to core::delaunay<D> (a flat grid gives no cells).
// Cells per grid cube: D = 3: 6, D = 4: 24 (the pattern's count).
// Complexity: O(n), parallel (TBB), without a sort: the cells under each
//   vertex come in one order for every vertex (grid_delaunay.cpp,
//   CanonicalSlots); memory: the output's 2 (D+1) 4-byte words per cell.

#include "core/simplex_mesh.hpp"

#include <array>

namespace ddt::core {

template <int D>
SimplexMesh<D> grid_delaunay(const std::array<int, D>& size);

// The cells and glue of grid_delaunay<D> alone (the caller has its points;
// 2D images keep theirs as Point2): every side at least 2. Returns false,
// leaving both arrays as they were, where the pattern does not repeat
// (a side of 1; a pattern whose opposite faces split differently, never
// seen): then core::delaunay<D> of the points is the answer.
// Errors: throws ddt::Error when the cells' ids would overflow index_t.
template <int D>
bool grid_delaunay_cells(const std::array<int, D>& size, std::vector<index_t>& cell, std::vector<index_t>& opp);

}  // namespace ddt::core
