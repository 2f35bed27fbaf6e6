// CGAL's Delaunay triangulations for the core (their headers stay here).
#include "core/delaunay.hpp"

#include "core/predicates.hpp"

#include <CGAL/Delaunay_triangulation.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Epick_d.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure.h>
#include <CGAL/Triangulation_full_cell.h>
#include <CGAL/Triangulation_vertex.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <map>
#include <utility>

namespace ddt::core {
namespace {

using Kernel23 = CGAL::Exact_predicates_inexact_constructions_kernel;

template <int D>
std::vector<CellVertices<D>> cgal_cells(const std::vector<Vec<D>>& points) {
  std::vector<CellVertices<D>> cells;
  if constexpr (D == 2) {
    using Vb = CGAL::Triangulation_vertex_base_with_info_2<index_t, Kernel23>;
    using Tds = CGAL::Triangulation_data_structure_2<Vb>;
    using Delaunay = CGAL::Delaunay_triangulation_2<Kernel23, Tds>;
    std::vector<std::pair<Kernel23::Point_2, index_t>> input;
    for (std::size_t i = 0; i < points.size(); ++i)
      input.emplace_back(Kernel23::Point_2(points[i][0], points[i][1]), static_cast<index_t>(i));
    const Delaunay dt(input.begin(), input.end());  // spatially sorted first
    if (dt.dimension() < 2) return cells;
    for (auto f : dt.finite_face_handles())
      cells.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  } else if constexpr (D == 3) {
    using Vb = CGAL::Triangulation_vertex_base_with_info_3<index_t, Kernel23>;
    using Tds = CGAL::Triangulation_data_structure_3<Vb>;
    using Delaunay = CGAL::Delaunay_triangulation_3<Kernel23, Tds>;
    std::vector<std::pair<Kernel23::Point_3, index_t>> input;
    for (std::size_t i = 0; i < points.size(); ++i)
      input.emplace_back(Kernel23::Point_3(points[i][0], points[i][1], points[i][2]), static_cast<index_t>(i));
    const Delaunay dt(input.begin(), input.end());
    if (dt.dimension() < 3) return cells;
    for (auto c : dt.finite_cell_handles())
      cells.push_back({c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()});
  } else {
    using Kernel = CGAL::Epick_d<CGAL::Dimension_tag<D>>;
    using Vb = CGAL::Triangulation_vertex<Kernel, index_t>;
    using Cb = CGAL::Triangulation_full_cell<Kernel>;
    using Tds = CGAL::Triangulation_data_structure<CGAL::Dimension_tag<D>, Vb, Cb>;
    using Delaunay = CGAL::Delaunay_triangulation<Kernel, Tds>;
    // The range insertion sorts spatially first; it loses the ids, which
    // come back through the coordinates (the points are distinct).
    std::vector<typename Kernel::Point_d> input;
    input.reserve(points.size());
    for (const Vec<D>& p : points) input.emplace_back(p.begin(), p.end());
    Delaunay dt(D);
    dt.insert(input.begin(), input.end());
    std::map<Vec<D>, index_t> id_of;
    for (std::size_t i = 0; i < points.size(); ++i) id_of.emplace(points[i], static_cast<index_t>(i));
    for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
      Vec<D> p;
      for (int k = 0; k < D; ++k) p[k] = v->point()[k];
      v->data() = id_of.at(p);
    }
    if (dt.current_dimension() < D) return cells;
    for (auto c = dt.finite_full_cells_begin(); c != dt.finite_full_cells_end(); ++c) {
      CellVertices<D> v;
      for (int i = 0; i <= D; ++i) v[i] = c->vertex(i)->data();
      cells.push_back(v);
    }
  }
  return cells;
}

}  // namespace

template <int D>
SimplexMesh<D> delaunay(const std::vector<Vec<D>>& points) {
  std::vector<CellVertices<D>> cells = cgal_cells<D>(points);
  // Canonical: ids ascending, the last two swapped for a positive order.
  for (CellVertices<D>& v : cells) {
    std::sort(v.begin(), v.end());
    if (orient_ids<D>(points, v) < 0) std::swap(v[D - 1], v[D]);
  }
  std::sort(cells.begin(), cells.end());
  SimplexMesh<D> mesh;
  mesh.points = points;
  mesh.cell.reserve(cells.size() * (D + 1));
  mesh.opp.reserve(cells.size() * (D + 1));
  for (const CellVertices<D>& v : cells) mesh.add_cell(v);
  link_facets(mesh);
  return mesh;
}

template SimplexMesh<2> delaunay<2>(const std::vector<Vec<2>>&);
template SimplexMesh<3> delaunay<3>(const std::vector<Vec<3>>&);
template SimplexMesh<4> delaunay<4>(const std::vector<Vec<4>>&);

}  // namespace ddt::core
