#include "triangulation.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
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

}  // namespace

bool violates_perturbed_delaunay(const Mesh2& mesh, index_t e) {
  const index_t f = mesh.opp[e];
  if (f == no_edge) return false;
  const std::array<index_t, 4> ids = {mesh.tri[e], mesh.tri[f], mesh.tri[prev_edge(e)],
                                      mesh.tri[prev_edge(f)]};  // a, b, c, d
  const auto& P = mesh.points;
  const Point2 &a = P[ids[0]], &b = P[ids[1]], &c = P[ids[2]], &d = P[ids[3]];
  const int exact = in_circle(a, b, c, d);
  if (exact != 0) return exact > 0;
  // Cocircular: the derivative of the determinant with respect to the
  // lifted height of each point is its cofactor, +-orientation of the other
  // three; the smallest id's term dominates.
  const int smallest = static_cast<int>(std::min_element(ids.begin(), ids.end()) - ids.begin());
  switch (smallest) {
    case 0: return orientation(b, c, d) > 0;
    case 1: return -orientation(a, c, d) > 0;
    case 2: return orientation(a, b, d) > 0;
    default: return -orientation(a, b, c) > 0;
  }
}

Mesh2 delaunay_triangulation(const std::vector<Point2>& points) {
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

  // Canonical order: rotate each face to start at its smallest id, sort.
  struct FaceRecord {
    std::array<index_t, 3> ids;
    int rotation;  // our slot k holds CGAL vertex (rotation + k) % 3
    Delaunay::Face_handle face;
  };
  std::vector<FaceRecord> faces;
  faces.reserve(dt.number_of_faces());
  for (auto fh : dt.finite_face_handles()) {
    std::array<index_t, 3> v = {fh->vertex(0)->info(), fh->vertex(1)->info(), fh->vertex(2)->info()};
    const int r = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
    faces.push_back({{v[r], v[(r + 1) % 3], v[(r + 2) % 3]}, r, fh});
  }
  std::sort(faces.begin(), faces.end(), [](const FaceRecord& x, const FaceRecord& y) { return x.ids < y.ids; });
  for (std::size_t t = 0; t < faces.size(); ++t) faces[t].face->info() = static_cast<index_t>(t);

  const index_t n_half = static_cast<index_t>(3 * faces.size());
  mesh.tri.resize(n_half);
  mesh.opp.assign(n_half, no_edge);
  for (std::size_t t = 0; t < faces.size(); ++t) {
    const FaceRecord& rec = faces[t];
    for (int k = 0; k < 3; ++k) {
      const index_t e = static_cast<index_t>(3 * t + k);
      mesh.tri[e] = rec.ids[k];
      // Half-edge slot k runs from CGAL vertex (r+k) to (r+k+1); the face
      // across it is the neighbour opposite CGAL vertex (r+k+2).
      auto nb = rec.face->neighbor((rec.rotation + k + 2) % 3);
      if (dt.is_infinite(nb)) continue;
      const index_t g = nb->info();
      const int j = nb->index(rec.face->vertex((rec.rotation + k + 1) % 3));
      mesh.opp[e] = 3 * g + (j - faces[g].rotation + 3) % 3;
    }
  }

  // Resolve cocircular ties by the perturbed criterion (plain Lawson).
  std::vector<index_t> stack;
  for (index_t e = 0; e < n_half; ++e)
    if (mesh.opp[e] > e) stack.push_back(e);
  while (!stack.empty()) {
    const index_t e = stack.back();
    stack.pop_back();
    if (!violates_perturbed_delaunay(mesh, e) || !is_flippable(mesh, e)) continue;
    const index_t f = mesh.opp[e];
    flip_edge(mesh, e);
    for (index_t h : {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)})
      if (mesh.opp[h] != no_edge) stack.push_back(h);
  }
  return mesh;
}

bool is_delaunay(const Mesh2& mesh) {
  for (index_t e = 0; e < mesh.half_edge_count(); ++e) {
    const index_t f = mesh.opp[e];
    if (f == no_edge) continue;
    const Point2& a = mesh.points[mesh.tri[e]];
    const Point2& b = mesh.points[mesh.tri[f]];
    const Point2& c = mesh.points[mesh.tri[prev_edge(e)]];
    const Point2& d = mesh.points[mesh.tri[prev_edge(f)]];
    if (in_circle(a, b, c, d) > 0) return false;
  }
  return true;
}

}  // namespace ddt
