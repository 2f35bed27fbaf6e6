#pragma once
// ddt::grid_tetrahedralization — the initial 3D mesh of a voxel grid: the
// Delaunay tetrahedrization of the voxel centres, as core::delaunay<3>
// (CGAL's Delaunay_triangulation_3) gives it, built in O(n) without a
// global Delaunay run.
//
// The Delaunay cells of a grid are its cubes (the 8 corners of a cube are
// cospherical, every other point lies outside their sphere). Where five or
// more points are cospherical CGAL resolves the tie by symbolic
// perturbation (Devillers & Teillaud, SODA 2003): points ordered
// lexicographically by (x, y, z), lifted by infinitesimals in that order.
// That refines each cube by the order of its corners, the same in every
// cube. So CGAL tetrahedrizes one 2x2x2 cube, and the pattern is repeated
// and put in core::delaunay's canonical order (each cell's ids ascending,
// the last two swapped for a positive orientation; cells sorted). The
// corner offsets grow with the corner number, so a translated cell keeps
// the pattern's order and orientation. Tests check the arrays equal
// core::delaunay<3>'s.
//
// Inputs: the grid size; points at voxel centres (x + 0.5, y + 0.5, z + 0.5),
// ids x fastest (as Volume::index). Grids with a side of 1 fall back to
// core::delaunay<3> (a flat grid gives no cells).
// Complexity: O(n log n) for the canonical sort, parallel (TBB).

#include "core/simplex_mesh.hpp"

namespace ddt {

core::SimplexMesh<3> grid_tetrahedralization(int nx, int ny, int nz);

}  // namespace ddt
