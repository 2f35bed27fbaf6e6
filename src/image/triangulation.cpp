#include "image/triangulation.hpp"

#include "core/check_mesh.hpp"
#include "core/grid_delaunay.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>

namespace ddt {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<index_t, Kernel>;
using FaceBase = CGAL::Triangulation_face_base_with_info_2<index_t, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;

Kernel::Point_2 cgal_point(const Point2& p) { return {p.x, p.y}; }

// Sign of the in-circle determinant of the lifted points (x, y, x^2+y^2, 1),
// positive when d lies inside the circle through counter-clockwise a, b, c.
int in_circle(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  return static_cast<int>(
      CGAL::side_of_oriented_circle(cgal_point(a), cgal_point(b), cgal_point(c), cgal_point(d)));
}

// The perturbed tie-break of the header, given the exact signs: `exact` the
// in-circle sign of (a, b, c, d) and orient(i) the orientation of the three
// points other than the i-th of (a, b, c, d) in the order the cofactor uses.
template <class Orient>
bool perturbed_violation(int exact, const std::array<index_t, 4>& ids, Orient orient) {
  if (exact != 0) return exact > 0;
  // Cocircular: the derivative of the determinant with respect to the
  // lifted height of each point is its cofactor, +-orientation of the other
  // three; the smallest id's term dominates.
  const int smallest = static_cast<int>(std::min_element(ids.begin(), ids.end()) - ids.begin());
  switch (smallest) {
    case 0: return orient(1, 2, 3) > 0;
    case 1: return -orient(0, 2, 3) > 0;
    case 2: return orient(0, 1, 3) > 0;
    default: return -orient(0, 1, 2) > 0;
  }
}

// Resolves cocircular ties by the perturbed criterion (plain Lawson from
// every interior edge). `violates(mesh, e)` and `flippable(mesh, e)` are
// exact. Returns the number of flips.
template <class Violates, class Flippable>
long long resolve_ties(Mesh2& mesh, Violates violates, Flippable flippable) {
  std::vector<index_t> stack;
  for (index_t e = 0; e < mesh.half_edge_count(); ++e)
    if (mesh.opp[e] > e) stack.push_back(e);
  long long flips = 0;
  while (!stack.empty()) {
    const index_t e = stack.back();
    stack.pop_back();
    if (!violates(mesh, e) || !flippable(mesh, e)) continue;
    const index_t f = mesh.opp[e];
    flip_edge(mesh, e);
    ++flips;
    for (index_t h : {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)})
      if (mesh.opp[h] != no_edge) stack.push_back(h);
  }
  return flips;
}

// Canonical order: each triangle rotated to start at its smallest vertex
// id, triangles sorted by their id triples; opp remapped. A counting sort
// on the smallest id, then a small sort within each bucket: O(#T + #V).
void canonicalize(std::vector<index_t>& tri, std::vector<index_t>& opp, std::size_t vertex_count) {
  const std::size_t T = tri.size() / 3;
  std::vector<std::uint8_t> rotation(T);
  std::vector<index_t> start(vertex_count + 1, 0);
  for (std::size_t t = 0; t < T; ++t) {
    const index_t* v = &tri[3 * t];
    const int r = v[0] < v[1] ? (v[0] < v[2] ? 0 : 2) : (v[1] < v[2] ? 1 : 2);
    rotation[t] = static_cast<std::uint8_t>(r);
    ++start[v[r] + 1];
  }
  for (std::size_t v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
  std::vector<index_t> order(T);  // order[rank] = old triangle
  {
    std::vector<index_t> cursor(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < T; ++t) order[cursor[tri[3 * t + rotation[t]]]++] = static_cast<index_t>(t);
  }
  auto key = [&](index_t t) {
    const index_t* v = &tri[3 * static_cast<std::size_t>(t)];
    const int r = rotation[t];
    return std::array<index_t, 2>{v[(r + 1) % 3], v[(r + 2) % 3]};
  };
  for (std::size_t v = 0; v < vertex_count; ++v)
    if (start[v + 1] - start[v] > 1)
      std::sort(order.begin() + start[v], order.begin() + start[v + 1],
                [&](index_t a, index_t b) { return key(a) < key(b); });
  std::vector<index_t> rank(T);
  for (std::size_t i = 0; i < T; ++i) rank[order[i]] = static_cast<index_t>(i);
  // Old half-edge 3t + j holds new slot (j - rotation + 3) % 3 of triangle rank[t].
  auto moved = [&](index_t h) {
    const index_t t = tri_of(h);
    return 3 * rank[t] + (h % 3 - rotation[t] + 3) % 3;
  };
  std::vector<index_t> new_tri(tri.size()), new_opp(opp.size());
  for (std::size_t h = 0; h < tri.size(); ++h) {
    const index_t m = moved(static_cast<index_t>(h));
    new_tri[m] = tri[h];
    new_opp[m] = opp[h] == no_edge ? no_edge : moved(opp[h]);
  }
  tri.swap(new_tri);
  opp.swap(new_opp);
}

// Flat arrays from a CGAL triangulation whose vertex infos are the ids.
template <class DT>
void flat_from_cgal(DT& dt, std::vector<index_t>& tri, std::vector<index_t>& opp) {
  index_t t = 0;
  for (auto fh : dt.finite_face_handles()) fh->info() = t++;
  tri.resize(3 * static_cast<std::size_t>(t));
  opp.assign(3 * static_cast<std::size_t>(t), no_edge);
  for (auto fh : dt.finite_face_handles()) {
    const index_t ft = fh->info();
    for (int k = 0; k < 3; ++k) {
      // Half-edge slot k runs from CGAL vertex k to k+1; the face across it
      // is the neighbour opposite vertex k+2.
      tri[3 * ft + k] = fh->vertex(k)->info();
      auto nb = fh->neighbor((k + 2) % 3);
      if (dt.is_infinite(nb)) continue;
      const int j = nb->index(fh->vertex((k + 1) % 3));  // nb's slot j starts at our vertex k+1
      opp[3 * ft + k] = 3 * nb->info() + j;
    }
  }
}

// ---------------------------------------------------------------------------
// Pixel grids: the Delaunay triangulation of a lattice repeats one cell's
// (core/grid_delaunay.hpp), equal to the perturbed one here (tests check
// it against Lawson's flips from either diagonal).

// True when points[i] == (x0 + i % W, y0 + i / W) for some W, H >= 2.
bool is_unit_grid(const std::vector<Point2>& points, int& W, int& H) {
  if (points.size() < 4) return false;
  const double x0 = points[0].x, y0 = points[0].y;
  std::size_t w = 1;
  while (w < points.size() && points[w].y == y0) ++w;
  if (w < 2 || points.size() % w != 0 || points.size() / w < 2) return false;
  if (points.size() > static_cast<std::size_t>(INT32_MAX) / 3) return false;
  const std::size_t h = points.size() / w;
  for (std::size_t y = 0; y < h; ++y)
    for (std::size_t x = 0; x < w; ++x) {
      const Point2& p = points[y * w + x];
      if (p.x != x0 + static_cast<double>(x) || p.y != y0 + static_cast<double>(y)) return false;
    }
  W = static_cast<int>(w);
  H = static_cast<int>(h);
  return true;
}

// The core's cells of the W x H grid as a Mesh2's triangles and twins (its
// points are the caller's): the same triangles, and facet slot
// 3t + (k + 2) % 3 is half-edge 3t + k (as_simplex_mesh).
bool grid_delaunay(int W, int H, Mesh2& mesh) {
  std::vector<index_t> facet_opp;
  if (!core::grid_delaunay_cells<2>({W, H}, mesh.tri, facet_opp)) return false;
  mesh.opp = std::move(facet_opp);
  auto half_edge = [](index_t slot) { return slot < 0 ? slot : 3 * tri_of(slot) + (slot % 3 + 1) % 3; };
  tbb::parallel_for(std::size_t(0), mesh.tri.size() / 3, [&](std::size_t t) {
    index_t* o = &mesh.opp[3 * t];
    const index_t across[3] = {half_edge(o[2]), half_edge(o[0]), half_edge(o[1])};
    std::copy(across, across + 3, o);
  });
  return true;
}

Mesh2 general_delaunay(const std::vector<Point2>& points) {
  Mesh2 mesh;
  mesh.points = points;
  std::vector<std::pair<Kernel::Point_2, index_t>> input;
  input.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    input.emplace_back(cgal_point(points[i]), static_cast<index_t>(i));
  // The range constructor sorts spatially (Hilbert order) before inserting.
  Delaunay dt(input.begin(), input.end());
  if (dt.dimension() < 2) return mesh;
  if (dt.number_of_vertices() < points.size()) {
    // Repeated positions: CGAL kept one copy, which depends on its order;
    // name each vertex by the smallest id at its position instead.
    std::map<std::pair<double, double>, index_t> first_id;
    for (std::size_t i = 0; i < points.size(); ++i)
      first_id.emplace(std::make_pair(points[i].x, points[i].y), static_cast<index_t>(i));
    for (auto vh : dt.finite_vertex_handles()) vh->info() = first_id.at({vh->point().x(), vh->point().y()});
  }
  flat_from_cgal(dt, mesh.tri, mesh.opp);
  dt.clear();
  canonicalize(mesh.tri, mesh.opp, points.size());
  // Sorted before the tie-break so that the flips it makes do not depend on
  // CGAL's face order (the flipped triangles keep their slots).
  resolve_ties(mesh, violates_perturbed_delaunay, is_flippable);
  return mesh;
}

}  // namespace

bool violates_perturbed_delaunay(const Mesh2& mesh, index_t e) {
  const index_t f = mesh.opp[e];
  if (f == no_edge) return false;
  const std::array<index_t, 4> ids = {mesh.tri[e], mesh.tri[f], mesh.tri[prev_edge(e)],
                                      mesh.tri[prev_edge(f)]};  // a, b, c, d
  const auto& P = mesh.points;
  const std::array<const Point2*, 4> p = {&P[ids[0]], &P[ids[1]], &P[ids[2]], &P[ids[3]]};
  return perturbed_violation(in_circle(*p[0], *p[1], *p[2], *p[3]), ids,
                             [&](int i, int j, int k) { return orientation(*p[i], *p[j], *p[k]); });
}

Mesh2 delaunay_triangulation(std::vector<Point2>&& points) {
  int W = 0, H = 0;
  Mesh2 grid;
  if (is_unit_grid(points, W, H) && grid_delaunay(W, H, grid)) {
    grid.points = std::move(points);
    return grid;
  }
  return general_delaunay(points);
}

Mesh2 delaunay_triangulation(const std::vector<Point2>& points) {
  return delaunay_triangulation(std::vector<Point2>(points));
}

bool is_delaunay(const Mesh2& mesh) { return core::is_delaunay<2>(as_simplex_mesh(mesh)); }

}  // namespace ddt
