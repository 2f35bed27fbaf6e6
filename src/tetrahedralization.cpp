#include "tetrahedralization.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <map>
#include <tuple>

namespace ddt {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<index_t, Kernel>;
using CellBase = CGAL::Triangulation_cell_base_with_info_3<index_t, Kernel, CGAL::Delaunay_triangulation_cell_base_3<Kernel>>;
using Tds = CGAL::Triangulation_data_structure_3<VertexBase, CellBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, Tds>;

Kernel::Point_3 cgal_point(const Point3& p) { return {p.x, p.y, p.z}; }

// Even permutations that bring position j to the front.
constexpr int front_perm[4][4] = {{0, 1, 2, 3}, {1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}};

}  // namespace

Mesh3 delaunay_tetrahedralization(const std::vector<Point3>& points) {
  Mesh3 mesh;
  mesh.points = points;
  std::vector<std::pair<Kernel::Point_3, index_t>> input;
  input.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) input.emplace_back(cgal_point(points[i]), static_cast<index_t>(i));
  // The range constructor sorts spatially (Hilbert order) before inserting.
  Delaunay dt(input.begin(), input.end());
  input.clear();
  input.shrink_to_fit();
  if (dt.dimension() < 3) return mesh;
  if (dt.number_of_vertices() < points.size()) {
    // Repeated positions: CGAL kept one copy, which depends on its order;
    // name each vertex by the smallest id at its position instead.
    std::map<std::tuple<double, double, double>, index_t> first_id;
    for (std::size_t i = 0; i < points.size(); ++i)
      first_id.emplace(std::make_tuple(points[i].x, points[i].y, points[i].z), static_cast<index_t>(i));
    for (auto vh : dt.finite_vertex_handles())
      vh->info() = first_id.at({vh->point().x(), vh->point().y(), vh->point().z()});
  }

  // Canonical order: smallest id first (even permutation), the other three
  // rotated to start at their smallest, then sorted.
  struct CellRecord {
    std::array<index_t, 4> ids;
    std::array<std::int8_t, 4> perm;  // our slot k holds CGAL vertex perm[k]
    Delaunay::Cell_handle cell;
  };
  std::vector<CellRecord> cells;
  cells.reserve(dt.number_of_finite_cells());
  for (auto ch : dt.finite_cell_handles()) {
    std::array<index_t, 4> v;
    for (int i = 0; i < 4; ++i) v[i] = ch->vertex(i)->info();
    const int j = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
    std::array<int, 4> p = {front_perm[j][0], front_perm[j][1], front_perm[j][2], front_perm[j][3]};
    // Rotate positions 1..3 cyclically so the smallest of them comes first.
    int r = 1;
    for (int k = 2; k < 4; ++k)
      if (v[p[k]] < v[p[r]]) r = k;
    const std::array<int, 4> q = {p[0], p[1 + (r - 1) % 3], p[1 + r % 3], p[1 + (r + 1) % 3]};
    CellRecord rec;
    for (int k = 0; k < 4; ++k) rec.ids[k] = v[q[k]], rec.perm[k] = static_cast<std::int8_t>(q[k]);
    rec.cell = ch;
    cells.push_back(rec);
  }
  std::sort(cells.begin(), cells.end(), [](const CellRecord& x, const CellRecord& y) { return x.ids < y.ids; });
  for (std::size_t t = 0; t < cells.size(); ++t) cells[t].cell->info() = static_cast<index_t>(t);

  const std::size_t n_slots = 4 * cells.size();
  mesh.tet.resize(n_slots);
  mesh.opp.assign(n_slots, no_face);
  for (std::size_t t = 0; t < cells.size(); ++t) {
    const CellRecord& rec = cells[t];
    for (int k = 0; k < 4; ++k) {
      mesh.tet[4 * t + k] = rec.ids[k];
      auto nb = rec.cell->neighbor(rec.perm[k]);  // across the face opposite our vertex k
      if (dt.is_infinite(nb)) continue;
      const index_t u = nb->info();
      const int j = nb->index(rec.cell);
      int local = 0;
      while (cells[u].perm[local] != j) ++local;
      mesh.opp[4 * t + k] = 4 * u + local;
    }
  }
  return mesh;
}

Mesh3 grid_tetrahedralization(int nx, int ny, int nz) {
  std::vector<Point3> points(static_cast<std::size_t>(nx) * ny * nz);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        points[(static_cast<std::size_t>(z) * ny + y) * nx + x] = {x + 0.5, y + 0.5, z + 0.5};
  if (nx < 2 || ny < 2 || nz < 2) return delaunay_tetrahedralization(points);

  // The cube pattern: CGAL on the 8 corners; corner c = dx + 2 dy + 4 dz.
  std::vector<Point3> corners;
  for (int c = 0; c < 8; ++c) corners.push_back({0.5 + (c & 1), 0.5 + (c >> 1 & 1), 0.5 + (c >> 2 & 1)});
  const Mesh3 cube = delaunay_tetrahedralization(corners);
  const int T = cube.tet_count();
  auto corner_of = [](index_t c, int axis) { return (c >> axis) & 1; };
  // Neighbour of face i of pattern tet p: same cube (step 0) or the cube
  // one step along +-axis; (q, j) its tet and face there, or q = -1 (hull).
  struct Across {
    int axis = -1, step = 0;
    int q = -1, j = -1;
  };
  std::vector<std::array<Across, 4>> across(T);
  for (int p = 0; p < T; ++p)
    for (int i = 0; i < 4; ++i) {
      Across& a = across[p][i];
      if (cube.opp[4 * p + i] != no_face) {
        a.q = tet_of(cube.opp[4 * p + i]);
        a.j = local_of(cube.opp[4 * p + i]);
        continue;
      }
      // A hull face of the cube lies on one of its six faces.
      std::array<index_t, 3> f;
      for (int k = 0; k < 3; ++k) f[k] = cube.tet[4 * p + face_vertex[i][k]];
      for (int axis = 0; axis < 3 && a.axis < 0; ++axis)
        for (int side = 0; side < 2 && a.axis < 0; ++side)
          if (corner_of(f[0], axis) == side && corner_of(f[1], axis) == side && corner_of(f[2], axis) == side) {
            a.axis = axis;
            a.step = side ? 1 : -1;
          }
      // The same three points seen from the next cube: flip that axis bit.
      std::array<index_t, 3> g;
      for (int k = 0; k < 3; ++k) g[k] = f[k] ^ (1 << a.axis);
      std::sort(g.begin(), g.end());
      for (int q = 0; q < T && a.q < 0; ++q)
        for (int j = 0; j < 4; ++j) {
          if (cube.opp[4 * q + j] != no_face) continue;
          std::array<index_t, 3> h;
          for (int k = 0; k < 3; ++k) h[k] = cube.tet[4 * q + face_vertex[j][k]];
          std::sort(h.begin(), h.end());
          if (h == g) {
            a.q = q;
            a.j = j;
            break;
          }
        }
    }
  for (const auto& faces : across)
    for (const Across& a : faces)
      if (a.q < 0) return delaunay_tetrahedralization(points);  // opposite cube faces split differently: never seen
  // Pattern tets in canonical rotation (translation keeps the id order);
  // their slots are already so (cube came from delaunay_tetrahedralization),
  // so our local index k is the pattern's local index k.
  const std::size_t cx = nx - 1, cy = ny - 1, cz = nz - 1, n_cubes = cx * cy * cz;
  const index_t offset[8] = {0, 1, nx, nx + 1, nx * ny, nx * ny + 1, nx * ny + nx, nx * ny + nx + 1};
  struct Record {
    std::array<index_t, 4> ids;
    index_t cube;
    std::int32_t p;
  };
  std::vector<Record> records(n_cubes * T);
  tbb::parallel_for(std::size_t(0), n_cubes, [&](std::size_t c) {
    const std::size_t x = c % cx, y = c / cx % cy, z = c / (cx * cy);
    const index_t base = static_cast<index_t>((z * ny + y) * nx + x);
    for (int p = 0; p < T; ++p) {
      Record& r = records[c * T + p];
      for (int k = 0; k < 4; ++k) r.ids[k] = base + offset[cube.tet[4 * p + k]];
      r.cube = static_cast<index_t>(c);
      r.p = p;
    }
  });
  tbb::parallel_sort(records.begin(), records.end(), [](const Record& a, const Record& b) { return a.ids < b.ids; });
  std::vector<index_t> slot_of(n_cubes * T);
  tbb::parallel_for(std::size_t(0), records.size(),
                    [&](std::size_t t) { slot_of[static_cast<std::size_t>(records[t].cube) * T + records[t].p] = static_cast<index_t>(t); });

  Mesh3 mesh;
  mesh.points = std::move(points);
  mesh.tet.resize(4 * records.size());
  mesh.opp.resize(4 * records.size());
  tbb::parallel_for(std::size_t(0), records.size(), [&](std::size_t t) {
    const Record& r = records[t];
    const std::size_t c = r.cube;
    const long long pos[3] = {static_cast<long long>(c % cx), static_cast<long long>(c / cx % cy),
                              static_cast<long long>(c / (cx * cy))};
    const long long size[3] = {static_cast<long long>(cx), static_cast<long long>(cy), static_cast<long long>(cz)};
    for (int k = 0; k < 4; ++k) {
      mesh.tet[4 * t + k] = r.ids[k];
      const Across& a = across[r.p][k];
      index_t target = no_face;
      if (a.axis < 0) {
        target = 4 * slot_of[c * T + a.q] + a.j;
      } else {
        long long next[3] = {pos[0], pos[1], pos[2]};
        next[a.axis] += a.step;
        if (next[a.axis] >= 0 && next[a.axis] < size[a.axis]) {
          const std::size_t c2 = static_cast<std::size_t>((next[2] * size[1] + next[1]) * size[0] + next[0]);
          target = 4 * slot_of[c2 * T + a.q] + a.j;
        }
      }
      mesh.opp[4 * t + k] = target;
    }
  });
  return mesh;
}

bool is_delaunay(const Mesh3& mesh) {
  const auto& P = mesh.points;
  for (index_t t = 0; t < mesh.slot_count(); ++t) {
    if (!mesh.is_live(t)) continue;
    const index_t* v = &mesh.tet[4 * t];
    for (int i = 0; i < 4; ++i) {
      const index_t g = mesh.opp[4 * t + i];
      if (g == no_face) continue;
      const Point3& e = P[mesh.tet[g]];
      if (CGAL::side_of_oriented_sphere(cgal_point(P[v[0]]), cgal_point(P[v[1]]), cgal_point(P[v[2]]),
                                        cgal_point(P[v[3]]), cgal_point(e)) == CGAL::ON_POSITIVE_SIDE)
        return false;
    }
  }
  return true;
}

bool cgal_is_valid(const Mesh3& mesh) {
  using Tr = CGAL::Triangulation_3<Kernel>;
  using VH = Tr::Vertex_handle;
  using CH = Tr::Cell_handle;
  Tr tr;
  auto& tds = tr.tds();
  tds.clear();
  const VH infinite = tds.create_vertex();
  tr.set_infinite_vertex(infinite);
  tds.set_dimension(3);

  std::vector<VH> vertex(mesh.points.size());
  for (index_t t = 0; t < mesh.slot_count(); ++t) {
    if (!mesh.is_live(t)) continue;
    for (int i = 0; i < 4; ++i) {
      const index_t v = mesh.tet[4 * t + i];
      if (v < 0 || v >= static_cast<index_t>(mesh.points.size())) return false;
      if (vertex[v] == VH()) {
        vertex[v] = tds.create_vertex();
        vertex[v]->set_point(cgal_point(mesh.points[v]));
      }
    }
  }
  std::vector<CH> cell(mesh.slot_count());
  for (index_t t = 0; t < mesh.slot_count(); ++t) {
    if (!mesh.is_live(t)) continue;
    const index_t* v = &mesh.tet[4 * t];
    cell[t] = tds.create_cell(vertex[v[0]], vertex[v[1]], vertex[v[2]], vertex[v[3]]);
    for (int i = 0; i < 4; ++i) vertex[v[i]]->set_cell(cell[t]);
  }
  if (tds.number_of_cells() == 0) return false;
  // Infinite cells over the hull faces, (a, c, b, infinite) for face (a, b, c)
  // read in face_vertex order, so they are oriented like their neighbours.
  std::map<std::pair<index_t, index_t>, std::vector<std::pair<CH, int>>> hull_edges;
  for (index_t t = 0; t < mesh.slot_count(); ++t) {
    if (!mesh.is_live(t)) continue;
    for (int i = 0; i < 4; ++i) {
      const index_t g = mesh.opp[4 * t + i];
      if (g != no_face) {
        if (g < 0 || g >= 4 * mesh.slot_count() || !mesh.is_live(tet_of(g))) return false;
        cell[t]->set_neighbor(i, cell[tet_of(g)]);
        continue;
      }
      const index_t a = mesh.tet[4 * t + face_vertex[i][0]], b = mesh.tet[4 * t + face_vertex[i][1]],
                    c = mesh.tet[4 * t + face_vertex[i][2]];
      const CH inf = tds.create_cell(vertex[a], vertex[c], vertex[b], infinite);
      infinite->set_cell(inf);
      inf->set_neighbor(3, cell[t]);
      cell[t]->set_neighbor(i, inf);
      // Face k of the infinite cell (opposite its vertex k, k < 3) holds the
      // hull edge of the other two finite vertices.
      const index_t ids[3] = {a, c, b};
      for (int k = 0; k < 3; ++k) {
        const index_t p = ids[(k + 1) % 3], q = ids[(k + 2) % 3];
        hull_edges[{std::min(p, q), std::max(p, q)}].emplace_back(inf, k);
      }
    }
  }
  for (const auto& [edge, sides] : hull_edges) {
    if (sides.size() != 2) return false;
    sides[0].first->set_neighbor(sides[0].second, sides[1].first);
    sides[1].first->set_neighbor(sides[1].second, sides[0].first);
  }
  return tr.is_valid(false);
}

}  // namespace ddt
