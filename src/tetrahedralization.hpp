#pragma once
// ddt::delaunay_tetrahedralization — the initial 3D mesh: the Delaunay
// tetrahedrization of arbitrary points, built by CGAL's
// Delaunay_triangulation_3 (Epick kernel, exact predicates) and handed over
// as flat arrays. Knows nothing of voxel grids. triangulation.hpp's 3D twin.
//
// Inputs:
//   points  #V positions; any order
// Outputs:
//   Mesh3 whose vertex ids are indices into `points`. Tetrahedra are in a
//   canonical order: each listed from its smallest id (an even permutation
//   of CGAL's, so still positively oriented) with the other three rotated to
//   start at their smallest, and the tetrahedra sorted by these quadruples.
//   Fewer than 4 points not all coplanar give a mesh with no tetrahedra.
//   Repeated positions: the smallest id at a position is used, the others
//   stay unreferenced.
//
// Ties: where five or more points are cospherical (every 2x2x2 cell of a
// voxel grid) Delaunay is ambiguous. CGAL resolves it by symbolic
// perturbation (Devillers & Teillaud, "Perturbations and vertex removal in
// a 3D Delaunay triangulation", SODA 2003): the points are ordered
// lexicographically by (x, y, z) and lifted by infinitesimals in that order,
// which makes the lifting generic. The result is the unique triangulation
// of that perturbed lifting: it depends on the coordinates alone, not on
// the insertion order or the ids (a test shuffles the input and compares).
// Complexity: O(V log V) expected; a voxel grid's degeneracies cost extra
// exact predicate evaluations.

#include "mesh3.hpp"

#include <vector>

namespace ddt {

Mesh3 delaunay_tetrahedralization(const std::vector<Point3>& points);

// The same mesh as delaunay_tetrahedralization of the voxel centres of an
// nx x ny x nz grid (ids x fastest, as Volume::index), built in O(n)
// without a global Delaunay run: the Delaunay cells of a grid are its
// cubes (the 8 corners of a cube are cospherical, every other point lies
// outside their sphere), and CGAL's perturbation refines each cube by the
// lexicographic order of its corners, the same in every cube. So CGAL
// tetrahedrizes one 2x2x2 cube, and the pattern is repeated and put in the
// canonical order. Tests check the arrays equal delaunay_tetrahedralization's.
// Grids with a side of 1 fall back to delaunay_tetrahedralization.
// Complexity: O(n log n) for the canonical sort, parallel (TBB).
Mesh3 grid_tetrahedralization(int nx, int ny, int nz);

// True when no vertex of a neighbouring tetrahedron lies strictly inside a
// tetrahedron's circumsphere (exact predicate), checked across every
// interior face (local Delaunay everywhere implies global Delaunay).
bool is_delaunay(const Mesh3& mesh);

// CGAL's own validity check on the mesh: copies it into a
// CGAL::Triangulation_3 (adding the infinite vertex and the infinite cells
// over the hull faces) and returns Triangulation_3::is_valid(): the data
// structure's combinatorial checks (neighbour symmetry, orientation
// consistency, vertex links, Euler relation) and the strict positive
// orientation of every finite cell. The mesh must use every point it
// references and have at least one tetrahedron. Meant for tests.
bool cgal_is_valid(const Mesh3& mesh);

}  // namespace ddt
