#include "image/triangulation.hpp"

#include "core/check_mesh.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <stdexcept>

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
// Pixel grids. The points are a row-major W x H lattice with unit spacing.
// Every 2x2 block of it is cocircular and no other lattice point lies in
// that circle, so every Delaunay triangulation (perturbed or not) splits
// each cell by one diagonal, and the perturbed choice depends only on the
// cell's four points. The lattice is therefore cut into blocks of cells;
// CGAL triangulates each block (its points in block-local integer
// coordinates), the tie-break is applied, and the blocks are stitched:
// the union is exactly the perturbed Delaunay triangulation of the whole
// grid, in the same canonical order. Blocks are small so that CGAL's
// structure stays in cache (its cost per point triples on large grids);
// block rows are built in parallel.
//
// Exactness: CGAL's Simple_cartesian<double> evaluates its predicates in
// plain double arithmetic. On integer coordinates below 2^12 every
// intermediate of orientation (< 2^25) and in-circle (< 8 * 2^48) is an
// integer below 2^53, hence exact; blocks are far smaller than that.

using GridKernel = CGAL::Simple_cartesian<double>;
using GridVertexBase = CGAL::Triangulation_vertex_base_with_info_2<index_t, GridKernel>;
using GridFaceBase = CGAL::Triangulation_face_base_with_info_2<index_t, GridKernel>;
using GridTds = CGAL::Triangulation_data_structure_2<GridVertexBase, GridFaceBase>;
using GridDelaunay = CGAL::Delaunay_triangulation_2<GridKernel, GridTds>;

constexpr int block_cells = 16;  // cells per block side (CPU time per point: 12-16 best, 32 1.6x)

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

// Hilbert-curve order of the points of a w x h block (row-major local ids).
std::vector<index_t> hilbert_order(int w, int h) {
  int n = 1;
  while (n < w || n < h) n *= 2;
  std::vector<index_t> order;
  order.reserve(static_cast<std::size_t>(w) * h);
  for (long d = 0; d < static_cast<long>(n) * n; ++d) {
    int x = 0, y = 0;
    long t = d;
    for (int s = 1; s < n; s *= 2) {
      const int rx = static_cast<int>(1 & (t / 2)), ry = static_cast<int>(1 & (t ^ rx));
      if (ry == 0) {
        if (rx == 1) x = s - 1 - x, y = s - 1 - y;
        std::swap(x, y);
      }
      x += s * rx;
      y += s * ry;
      t /= 4;
    }
    if (x < w && y < h) order.push_back(y * w + x);
  }
  return order;
}

// Orientation and in-circle on block-local integer coordinates, in
// GridKernel's plain double arithmetic: exact there (see above).
using GridPoint = GridKernel::Point_2;
int orient_int(const GridPoint& p, const GridPoint& q, const GridPoint& r) {
  return static_cast<int>(CGAL::orientation(p, q, r));
}
int in_circle_int(const GridPoint& a, const GridPoint& b, const GridPoint& c, const GridPoint& d) {
  return static_cast<int>(CGAL::side_of_oriented_circle(a, b, c, d));
}

// The perturbed Delaunay triangulation of the block of lattice points
// (x, y), 0 <= x < w, whose local ids y * w + x `order` lists, in CGAL's
// face order (sorted when stitched).
void triangulate_block(int w, const std::vector<index_t>& order, std::vector<index_t>& tri,
                       std::vector<index_t>& opp) {
  GridDelaunay dt;
  GridDelaunay::Face_handle hint;
  for (index_t id : order) {
    auto vh = dt.insert(GridKernel::Point_2(id % w, id / w), hint);
    vh->info() = id;
    hint = vh->face();
  }
  flat_from_cgal(dt, tri, opp);
  Mesh2 local;
  local.tri.swap(tri);
  local.opp.swap(opp);
  auto at = [w](index_t id) { return GridPoint(id % w, id / w); };
  auto violates = [&](const Mesh2& m, index_t e) {
    const index_t f = m.opp[e];
    if (f == no_edge) return false;
    const std::array<index_t, 4> ids = {m.tri[e], m.tri[f], m.tri[prev_edge(e)], m.tri[prev_edge(f)]};
    const std::array<GridPoint, 4> p = {at(ids[0]), at(ids[1]), at(ids[2]), at(ids[3])};
    return perturbed_violation(in_circle_int(p[0], p[1], p[2], p[3]), ids,
                               [&](int i, int j, int k) { return orient_int(p[i], p[j], p[k]); });
  };
  auto flippable = [&](const Mesh2& m, index_t e) {
    const index_t f = m.opp[e];
    const GridPoint a = at(m.tri[e]), b = at(m.tri[f]), c = at(m.tri[prev_edge(e)]), d = at(m.tri[prev_edge(f)]);
    return orient_int(d, c, a) > 0 && orient_int(c, d, b) > 0;
  };
  resolve_ties(local, violates, flippable);
  tri.swap(local.tri);
  opp.swap(local.opp);
}

Mesh2 grid_delaunay(const std::vector<Point2>& points, int W, int H) {
  Mesh2 mesh;
  mesh.points = points;
  const int cells_x = W - 1, cells_y = H - 1;
  const std::size_t row_tris = 2 * static_cast<std::size_t>(cells_x);  // triangles per row of cells
  mesh.tri.assign(3 * row_tris * cells_y, index_t(0));
  mesh.opp.assign(mesh.tri.size(), index_t(0));
  const int blocks_x = (cells_x + block_cells - 1) / block_cells;
  const int blocks_y = (cells_y + block_cells - 1) / block_cells;
  const std::vector<index_t> full_order = hilbert_order(block_cells + 1, block_cells + 1);

  // top[j][x]: the half-edge of block row j along its top side, from (x, y0)
  // to (x + 1, y0) or back; bottom[j][x] likewise. Linked once all rows exist.
  std::vector<std::vector<index_t>> top(blocks_y), bottom(blocks_y);
  std::vector<char> failed(blocks_y, 0);

  tbb::parallel_for(0, blocks_y, [&](int j) {
    const int cy0 = j * block_cells, cy1 = std::min(cells_y, cy0 + block_cells);
    const std::size_t base = row_tris * cy0;  // first triangle of this block row
    const std::size_t count = row_tris * (cy1 - cy0);
    // Triangles of the block row keyed by their smallest vertex, which lies
    // on rows cy0 .. cy1 - 1 (each triangle is half a cell).
    const std::size_t first_vertex = static_cast<std::size_t>(cy0) * W;
    const std::size_t key_range = static_cast<std::size_t>(cy1 - cy0) * W;
    struct Record {
      index_t ids[3];        // global ids, rotated to start at the smallest
      index_t local_opp[3];  // twins as half-edges of the block's own numbering
      int block;
      int rotation;          // slot k holds the block's slot (rotation + k) % 3
    };
    std::vector<Record> records;
    records.reserve(count);
    std::vector<index_t> block_first(blocks_x + 1, 0);  // first record of each block
    std::vector<index_t> tri, opp;
    for (int i = 0; i < blocks_x; ++i) {
      const int cx0 = i * block_cells, cx1 = std::min(cells_x, cx0 + block_cells);
      const int w = cx1 - cx0 + 1, h = cy1 - cy0 + 1;
      triangulate_block(w, w == block_cells + 1 && h == block_cells + 1 ? full_order : hilbert_order(w, h), tri, opp);
      block_first[i] = static_cast<index_t>(records.size());
      for (std::size_t t = 0; t < tri.size() / 3; ++t) {
        const index_t* v = &tri[3 * t];
        Record r;
        r.rotation = v[0] < v[1] ? (v[0] < v[2] ? 0 : 2) : (v[1] < v[2] ? 1 : 2);
        for (int k = 0; k < 3; ++k) {
          const index_t id = v[(r.rotation + k) % 3];
          r.ids[k] = (cy0 + id / w) * W + (cx0 + id % w);  // monotone: local order is global order
          r.local_opp[k] = opp[3 * t + (r.rotation + k) % 3];
        }
        r.block = i;
        records.push_back(r);
      }
    }
    block_first[blocks_x] = static_cast<index_t>(records.size());
    if (records.size() != count) {
      failed[j] = 1;
      return;
    }
    // Counting sort by smallest id; ties (a vertex on a vertical seam can
    // be the smallest of triangles in two blocks) sorted by the others.
    std::vector<index_t> start(key_range + 1, 0);
    for (const Record& r : records) {
      const std::size_t key = static_cast<std::size_t>(r.ids[0]) - first_vertex;
      if (r.ids[0] < static_cast<index_t>(first_vertex) || key >= key_range) {
        failed[j] = 1;
        return;
      }
      ++start[key + 1];
    }
    for (std::size_t k = 0; k < key_range; ++k) start[k + 1] += start[k];
    std::vector<index_t> rank(records.size());
    {
      std::vector<index_t> cursor(start.begin(), start.end() - 1);
      std::vector<index_t> order(records.size());
      for (std::size_t r = 0; r < records.size(); ++r)
        order[cursor[records[r].ids[0] - first_vertex]++] = static_cast<index_t>(r);
      for (std::size_t k = 0; k < key_range; ++k)
        if (start[k + 1] - start[k] > 1)
          std::sort(order.begin() + start[k], order.begin() + start[k + 1], [&](index_t a, index_t b) {
            return std::array<index_t, 2>{records[a].ids[1], records[a].ids[2]} <
                   std::array<index_t, 2>{records[b].ids[1], records[b].ids[2]};
          });
      for (std::size_t r = 0; r < order.size(); ++r) rank[order[r]] = static_cast<index_t>(r);
    }
    // Write triangles and the twins inside blocks; collect seam edges.
    std::vector<std::pair<std::int64_t, index_t>> vertical;  // (edge key, global half-edge)
    top[j].assign(W - 1, no_edge);
    bottom[j].assign(W - 1, no_edge);
    for (std::size_t r = 0; r < records.size(); ++r) {
      const Record& rec = records[r];
      const std::size_t t = base + rank[r];
      for (int k = 0; k < 3; ++k) {
        const index_t e = static_cast<index_t>(3 * t + k);
        mesh.tri[e] = rec.ids[k];
        const index_t lo = rec.local_opp[k];
        if (lo != no_edge) {
          const index_t twin = block_first[rec.block] + lo / 3;
          mesh.opp[e] = static_cast<index_t>(3 * (base + rank[twin]) + (lo % 3 - records[twin].rotation + 3) % 3);
          continue;
        }
        mesh.opp[e] = no_edge;
        const index_t u = rec.ids[k], v = rec.ids[(k + 1) % 3];
        const index_t lo_id = std::min(u, v);
        const int x = lo_id % W, y = lo_id / W;
        if (u / W == v / W) {  // horizontal hull edge of the block: top or bottom side
          if (y == cy0 && y > 0) top[j][x] = e;
          if (y == cy1 && y < cells_y) bottom[j][x] = e;
        } else if (x > 0 && x < cells_x) {  // vertical, on a seam between blocks
          vertical.emplace_back(static_cast<std::int64_t>(lo_id), e);
        }
      }
    }
    std::sort(vertical.begin(), vertical.end());
    for (std::size_t k = 0; k + 1 < vertical.size(); k += 2) {
      if (vertical[k].first != vertical[k + 1].first) {
        failed[j] = 1;
        return;
      }
      mesh.link(vertical[k].second, vertical[k + 1].second);
    }
    if (vertical.size() % 2 != 0) failed[j] = 1;
  });
  for (int j = 0; j + 1 < blocks_y; ++j)
    for (int x = 0; x < W - 1; ++x) {
      if (bottom[j][x] == no_edge || top[j + 1][x] == no_edge) failed[j] = 1;
      else mesh.link(bottom[j][x], top[j + 1][x]);
    }
  if (std::find(failed.begin(), failed.end(), 1) != failed.end())
    throw std::logic_error("grid_delaunay: a block did not triangulate as a lattice");  // never expected
  return mesh;
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

Mesh2 delaunay_triangulation(const std::vector<Point2>& points) {
  int W = 0, H = 0;
  if (is_unit_grid(points, W, H)) return grid_delaunay(points, W, H);
  return general_delaunay(points);
}

bool is_delaunay(const Mesh2& mesh) { return core::is_delaunay<2>(as_simplex_mesh(mesh)); }

}  // namespace ddt
