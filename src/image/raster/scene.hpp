#pragma once
// ddt::raster — the rasterizer's internals (image/rasterizer.hpp is the
// contract): the scene it draws (the mesh plus its rim), and the small
// exact-arithmetic helpers every part shares. Used by image/rasterizer.cpp
// and the files of image/raster/ only.

#include "core/predicates.hpp"
#include "image/mesh.hpp"
#include "image/rasterizer.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace ddt::raster {

constexpr int max_channels = 16;

// Side of p relative to the directed line u->v on a tie (p on the line):
// core::perturbed_tie, p moved by (eps, eps^2): +1 left, -1 right, never 0
// for u != v. Antisymmetric in (u, v), so two triangles sharing an edge
// never both own a point on it.
inline int tie_side(const Point2& u, const Point2& v) {
  return core::perturbed_tie<2>({core::Vec<2>{u.x, u.y}, core::Vec<2>{v.x, v.y}});
}

// The surface's geometry: the mesh's triangles, then the rim's (slabs and
// fans outside the hull). Vertex ids below V are the mesh's; id V + i is
// rim vertex i, which carries the value (and gradient) of mesh vertex
// rim_source[i]. It depends on the mesh and the grid only, so a
// RenderPlan keeps it for every call (rasterizer.hpp).
struct SceneGeometry {
  SceneGeometry(const Mesh2& m, const RenderGrid& g) : mesh(m), grid(g) {}

  const Mesh2& mesh;
  RenderGrid grid;  // its rows unused
  index_t V = 0, T = 0;
  std::vector<Point2> rim_points;  // input coordinates
  std::vector<index_t> rim_source;
  std::vector<index_t> rim_tris;   // counter-clockwise triples
  // Exactness: when every drawn coordinate is a multiple of 2^-10 below 2^15
  // in magnitude (and pixel centres are integers below 2^15), edge functions
  // at pixel centres are exact in double: differences are multiples of
  // 2^-10 below 2^16 (26 bits), products multiples of 2^-20 below 2^32
  // (52 bits), their difference below 2^33 (53 bits). Integer scales and
  // most others (2.5, 0.75, ...) qualify; the rest take a filtered path.
  bool mesh_exact = false;
  std::vector<char> rim_exact;
  // The rim of a convex hull overlaps no triangle; elsewhere its slabs can
  // reach over the mesh, and what they cover depends on the drawing order.
  bool hull_convex = false;

  index_t triangle_count() const { return T + static_cast<index_t>(rim_tris.size() / 3); }
  void corners(index_t t, index_t out[3]) const {
    const index_t* src = t < T ? &mesh.tri[3 * static_cast<std::size_t>(t)] : &rim_tris[3 * static_cast<std::size_t>(t - T)];
    out[0] = src[0], out[1] = src[1], out[2] = src[2];
  }
  const Point2& input_point(index_t v) const { return v < V ? mesh.points[v] : rim_points[v - V]; }
  // Output pixel space: pixel centres at integers.
  Point2 transform(const Point2& p) const {
    return {(p.x - grid.origin_x) * grid.scale_x - 0.5, (p.y - grid.origin_y) * grid.scale_y - 0.5};
  }
  // Computed where needed: as cheap as loading a stored copy, and no
  // memory to allocate (fresh pages cost more than the arithmetic).
  Point2 pos(index_t v) const { return transform(input_point(v)); }
  index_t source(index_t v) const { return v < V ? v : rim_source[v - V]; }
  bool exact(index_t v) const { return v < V ? mesh_exact : rim_exact[v - V] != 0; }

  // Half-edges: 3t + k runs from corner k of triangle t to corner k + 1
  // (mesh triangles first, then the rim's, as the triangle ids).
  // rim_twin[i] is the twin of rim half-edge 3T + i; hull_twin maps each
  // hull half-edge of the mesh to its rim twin (sorted).
  std::vector<index_t> hull;  // the mesh's hull half-edges
  std::vector<index_t> rim_twin;
  std::vector<std::pair<index_t, index_t>> hull_twin;
  index_t tail(index_t e) const {
    return e < 3 * T ? mesh.tri[e] : rim_tris[static_cast<std::size_t>(e - 3 * T)];
  }
  index_t twin(index_t e) const {
    if (e >= 3 * T) return rim_twin[static_cast<std::size_t>(e - 3 * T)];
    if (mesh.opp[e] != no_edge || hull_twin.empty()) return mesh.opp[e];
    const auto it = std::lower_bound(hull_twin.begin(), hull_twin.end(), std::make_pair(e, index_t(-1)));
    return it != hull_twin.end() && it->first == e ? it->second : no_edge;
  }
};

// One drawing of the geometry: the vertices' values (and gradients).
struct Scene {
  Scene(const SceneGeometry& g, const std::vector<float>& v, int channels)
      : geometry(g), mesh(g.mesh), grid(g.grid), V(g.V), T(g.T), values(v), C(channels) {}

  const SceneGeometry& geometry;
  const Mesh2& mesh;
  const RenderGrid& grid;
  index_t V, T;
  const std::vector<float>& values;
  int C;
  const VertexValues* window = nullptr;  // set: linear mode reads only these vertices' values
  const std::vector<float>* gradients = nullptr;  // cubic mode: every vertex's
  const VertexValues* gradient_window = nullptr;  // cubic mode: or those of a window of vertices
  bool add = false;  // linear mode: values added to the pixels' own (add_mesh_render_into)
  // Cubic mode: the Bézier control values of each rim triangle, C each.
  std::vector<std::array<double, 10>> rim_patches;

  index_t triangle_count() const { return geometry.triangle_count(); }
  void corners(index_t t, index_t out[3]) const { geometry.corners(t, out); }
  const Point2& input_point(index_t v) const { return geometry.input_point(v); }
  Point2 pos(index_t v) const { return geometry.pos(v); }
  index_t source(index_t v) const { return geometry.source(v); }
  const float* value(index_t v) const {
    if (!window) return &values[static_cast<std::size_t>(source(v)) * C];
    const index_t s = source(v);
    if (s < window->first || s >= window->end) throw Error("render_mesh: a vertex beyond the window of values");
    return window->data + static_cast<std::size_t>(s - window->first) * C;
  }
  // Cubic mode: vertex v's 2 C gradient components (x, y per channel).
  const float* gradient(index_t v) const {
    if (!gradient_window) return &(*gradients)[static_cast<std::size_t>(v) * C * 2];
    if (v < gradient_window->first || v >= gradient_window->end)
      throw Error("render_mesh: a vertex beyond the window of gradients");
    return gradient_window->data + static_cast<std::size_t>(v - gradient_window->first) * C * 2;
  }
  bool exact(index_t v) const { return geometry.exact(v); }
  index_t tail(index_t e) const { return geometry.tail(e); }
  index_t twin(index_t e) const { return geometry.twin(e); }
};

// floor and ceil for values well inside the int range (pixel coordinates,
// clamped by the callers): a truncation and a correction, much cheaper
// than std::floor without SSE4.1.
inline int floor_int(double v) {
  const int i = static_cast<int>(v);
  return i - (v < i);
}
inline int ceil_int(double v) {
  const int i = static_cast<int>(v);
  return i + (v > i);
}
// Clamps v into [lo, hi] before the conversion (coordinates of far rim
// vertices, in pixels, can exceed the int range).
inline double clamp_pixels(double v) { return std::clamp(v, -1e9, 1e9); }

// Exactness of the edge functions (see Scene::mesh_exact): the lattice of
// multiples of 2^-10 below 2^15.
inline bool exact_coordinate(double c) { return core::on_lattice(c, 10, 32768.0); }

// Adds the slabs and corner fans that extend the hull's values outward
// (raster/rim.cpp). Precondition: geometry.hull set.
void add_rim(SceneGeometry& geometry);
// Cubic mode: the rim triangles' patches for the scene's values and
// gradients (Scene::rim_patches).
std::vector<std::array<double, 10>> make_rim_patches(const Scene& scene);

// The cubic patch of scene triangle t (corners i) for channel c.
std::array<double, 10> scene_patch(const Scene& scene, index_t t, const index_t i[3], int c);

// A mesh with no triangles: linear interpolation along the line of its
// points, clamped at the ends (raster/collinear.cpp). Rows [row0, row1).
Image render_collinear(const Mesh2& mesh, const std::vector<float>& values, int C, const RenderGrid& grid, int row0,
                       int row1);

}  // namespace ddt::raster
