// CGAL's Delaunay triangulations for the core (their headers stay here).
#include "core/delaunay.hpp"

#include "core/predicates.hpp"
#include "util/error.hpp"
#include "util/thread_limit.hpp"

#include <tbb/parallel_for.h>

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
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
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

// D = 3, the large case (image sequences sheared along their motion):
// glued from CGAL's own neighbours instead of by link_facets, which sorts
// every facet; the same arrays.
SimplexMesh<3> glued_delaunay_3(const std::vector<Vec<3>>& points) {
  using Vb = CGAL::Triangulation_vertex_base_with_info_3<index_t, Kernel23>;
  using Cb = CGAL::Triangulation_cell_base_with_info_3<index_t, Kernel23, CGAL::Delaunay_triangulation_cell_base_3<Kernel23>>;
  using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb>;
  using Delaunay = CGAL::Delaunay_triangulation_3<Kernel23, Tds>;
  SimplexMesh<3> mesh;
  mesh.points = points;
  std::vector<CellVertices<3>> canonical;
  std::vector<std::array<std::int8_t, 4>> slot_of;  // CGAL's local index -> canonical slot
  std::vector<index_t> rank;
  {
    std::vector<std::pair<Kernel23::Point_3, index_t>> input;
    input.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
      input.emplace_back(Kernel23::Point_3(points[i][0], points[i][1], points[i][2]), static_cast<index_t>(i));
    Delaunay dt(input.begin(), input.end());
    input = {};
    if (dt.dimension() < 3) return mesh;
    index_t k = 0;
    for (auto c : dt.finite_cell_handles()) {
      c->info() = k++;
      std::array<std::pair<index_t, int>, 4> by_id;
      for (int i = 0; i < 4; ++i) by_id[i] = {c->vertex(i)->info(), i};
      std::sort(by_id.begin(), by_id.end());
      CellVertices<3> v{by_id[0].first, by_id[1].first, by_id[2].first, by_id[3].first};
      if (orient_ids<3>(points, v) < 0) std::swap(v[2], v[3]), std::swap(by_id[2], by_id[3]);
      std::array<std::int8_t, 4> slots{};
      for (int s = 0; s < 4; ++s) slots[by_id[s].second] = static_cast<std::int8_t>(s);
      canonical.push_back(v);
      slot_of.push_back(slots);
    }
    if (canonical.size() > static_cast<std::size_t>(std::numeric_limits<index_t>::max() / 4))
      throw Error("the triangulation has too many tetrahedra for 32-bit facet ids");
    std::vector<index_t> order(canonical.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<index_t>(i);
    std::sort(order.begin(), order.end(), [&](index_t a, index_t b) { return canonical[a] < canonical[b]; });
    rank.resize(order.size());
    mesh.cell.reserve(4 * order.size());
    for (std::size_t r = 0; r < order.size(); ++r) {
      rank[order[r]] = static_cast<index_t>(r);
      mesh.cell.insert(mesh.cell.end(), canonical[order[r]].begin(), canonical[order[r]].end());
    }
    canonical = {};
    mesh.opp.assign(4 * order.size(), no_facet);
    for (auto c : dt.finite_cell_handles())
      for (int i = 0; i < 4; ++i) {
        const auto n = c->neighbor(i);
        if (dt.is_infinite(n)) continue;
        const index_t a = c->info(), b = n->info();
        mesh.opp[4 * rank[a] + slot_of[a][i]] = 4 * rank[b] + slot_of[b][n->index(c)];
      }
  }
  return mesh;
}

}  // namespace

template <int D>
SimplexMesh<D> delaunay(const std::vector<Vec<D>>& points) {
  if constexpr (D == 3) {
    return glued_delaunay_3(points);
  } else {
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
}

bool layered_delaunay(const std::vector<Vec<3>>& points, index_t layer_size, SimplexMesh<3>& mesh) {
  // About 6 cells a point, 4 facet ids each: refused before any work.
  if (points.size() > static_cast<std::size_t>(std::numeric_limits<index_t>::max()) / 28)
    throw Error("a triangulation of " + std::to_string(points.size()) + " points has too many tetrahedra for 32-bit ids");
  const index_t n = static_cast<index_t>(points.size());
  if (layer_size < 1 || n % layer_size != 0 || n / layer_size < 2) return false;
  const index_t slabs = n / layer_size - 1;
  using Triple = std::array<index_t, 3>;
  struct Slab {
    SimplexMesh<3> mesh;  // over global ids
    std::vector<std::pair<Triple, index_t>> bottom, top;  // hull facets in the slab's first / second layer
  };
  auto triangulate = [&](index_t s, Slab& slab) {
    const index_t first = s * layer_size;
    slab.mesh = glued_delaunay_3(std::vector<Vec<3>>(points.begin() + first, points.begin() + first + 2 * layer_size));
    slab.mesh.points = {};
    for (index_t& v : slab.mesh.cell) v += first;
    const index_t facets = static_cast<index_t>(slab.mesh.opp.size());
    for (index_t f = 0; f < facets; ++f) {
      if (slab.mesh.opp[f] != no_facet) continue;
      Triple t{};
      for (int j = 0, k = 0; j < 4; ++j)
        if (j != local_of<3>(f)) t[k++] = slab.mesh.cell[4 * cell_of<3>(f) + j];
      std::sort(t.begin(), t.end());
      if (t[2] < first + layer_size) slab.bottom.emplace_back(t, f);
      else if (t[0] >= first + layer_size) slab.top.emplace_back(t, f);
    }
    std::sort(slab.bottom.begin(), slab.bottom.end());
    std::sort(slab.top.begin(), slab.top.end());
  };
  // A few slabs at a time (one a thread), appended in order and freed, so
  // that no more than those are held beside the result.
  SimplexMesh<3> glued;
  glued.points = points;
  const std::size_t expected = 4 * std::size_t(7) * static_cast<std::size_t>(layer_size) * slabs;  // ~6 cells a sample
  glued.cell.reserve(expected);
  glued.opp.reserve(expected);
  const index_t batch = allowed_threads();
  std::vector<std::pair<Triple, index_t>> previous_top;  // in glued's facet ids
  for (index_t s0 = 0; s0 < slabs; s0 += batch) {
    const index_t count = std::min(batch, slabs - s0);
    std::vector<Slab> batch_slabs(static_cast<std::size_t>(count));
    tbb::parallel_for(index_t(0), count, [&](index_t i) { triangulate(s0 + i, batch_slabs[std::size_t(i)]); });
    for (Slab& slab : batch_slabs) {
      if (slab.mesh.cell.empty()) return false;
      if (glued.opp.size() + slab.mesh.opp.size() > static_cast<std::size_t>(std::numeric_limits<index_t>::max()))
        throw Error("the triangulation has too many tetrahedra for 32-bit facet ids");
      const index_t offset = static_cast<index_t>(glued.opp.size());
      if (offset > 0) {  // the shared layer's faces must be the same triangles
        if (previous_top.size() != slab.bottom.size()) return false;
        for (std::size_t i = 0; i < previous_top.size(); ++i)
          if (previous_top[i].first != slab.bottom[i].first) return false;
      }
      glued.cell.insert(glued.cell.end(), slab.mesh.cell.begin(), slab.mesh.cell.end());
      for (const index_t g : slab.mesh.opp) glued.opp.push_back(g == no_facet ? no_facet : g + offset);
      if (offset > 0)
        for (std::size_t i = 0; i < previous_top.size(); ++i) {
          const index_t f = slab.bottom[i].second + offset, g = previous_top[i].second;
          glued.opp[f] = g;
          glued.opp[g] = f;
        }
      previous_top = std::move(slab.top);
      for (auto& facet : previous_top) facet.second += offset;
      slab = {};
    }
  }
  glued.cell.shrink_to_fit();
  glued.opp.shrink_to_fit();
  mesh = std::move(glued);
  return true;
}

template SimplexMesh<2> delaunay<2>(const std::vector<Vec<2>>&);
template SimplexMesh<3> delaunay<3>(const std::vector<Vec<3>>&);
template SimplexMesh<4> delaunay<4>(const std::vector<Vec<4>>&);

}  // namespace ddt::core
