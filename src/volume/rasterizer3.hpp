#pragma once
// Scan conversion of piecewise-linear fields on tetrahedral meshes into a
// voxel grid (rasterizer.hpp's 3D twin).
//
// Output voxel (X, Y, Z) samples the input space at
//     ((X + 0.5) / scale_x, (Y + 0.5) / scale_y, (Z + 0.5) / scale_z),
// the voxel convention of volume.hpp. Inside the convex hull of the mesh
// the value is the linear interpolant of the tetrahedron containing that
// point; outside it, the value at the nearest point of the hull.
//
// Fill rule: every sample point is owned by at most one tetrahedron.
// Coverage uses CGAL's exact orientation predicate; a point exactly on a
// face, edge or vertex belongs to the tetrahedron that contains the point
// moved by an infinitesimal (eps, eps^2, eps^3), so two tetrahedra sharing
// a face never both own a point on it. Interpolation uses barycentric
// weights computed so that, on a voxel grid (where coordinate differences
// are exact), they are exactly 1 and 0 at the vertices: samples that
// coincide with output voxel centres (odd integer scales) are reproduced
// bit for bit.
//
// Hull rim: the hull must be an axis-aligned box (true of every voxel grid:
// the box [0.5, n - 0.5] per axis). The nearest hull point is then the
// sample clamped into the box, and its value is the 2D piecewise-linear
// field on the hull triangles of that box face, rendered per face by the
// 2D rasterizer (rasterizer.hpp) with its own exact rule and rim, which is
// clamping again. Samples on the hull itself that no tetrahedron owns (the
// perturbation pushes them out) take the same face value, which equals the
// interpolant there.
//
// Work is parallel over tetrahedra (TBB): each voxel has a single owner, so
// writes never collide.
//
// Errors: throws ddt::Error when the mesh has no tetrahedra or its hull is
// not an axis-aligned box.

#include "core/simplex_mesh.hpp"
#include "volume/volume.hpp"

#include <vector>

namespace ddt {

struct VolumeGrid {
  int nx = 0, ny = 0, nz = 0;                 // output size in voxels
  double scale_x = 1, scale_y = 1, scale_z = 1;  // output voxels per input unit
};

struct Render3Stats {
  long long tetrahedra = 0;   // mesh tetrahedra drawn
  long long owned = 0;        // voxels owned by a tetrahedron
  long long rim = 0;          // voxels given their nearest hull point's value
  long long uncovered = 0;    // voxels inside the hull no tetrahedron owned (0 unless degenerate)
  long long overcovered = 0;  // voxels owned twice (always 0; checked)
};

// Inputs:
//   mesh    valid core::SimplexMesh<3> (points in input coordinates) whose hull is a box
//   values  #V vertex values (one channel)
//   grid    output size and sampling
// Output: grid.nx x grid.ny x grid.nz volume.
Volume render_tetrahedra(const core::SimplexMesh<3>& mesh, const std::vector<float>& values, const VolumeGrid& grid,
                         Render3Stats* stats = nullptr);

}  // namespace ddt
