#pragma once
// ddt::core::SimplexMesh<D> — a D-dimensional simplicial mesh as flat arrays,
// the one layout every dimension shares (the volume path uses D = 3).
//
// Numbering convention
//   Cell c owns slots (D+1)c .. (D+1)c + D. cell[(D+1)c + i] is its vertex i;
//   slot (D+1)c + i also names its FACET i, the (D-1)-simplex opposite
//   vertex i (the other D vertices, in increasing local order).
//   Cells are positively oriented: orient<D>(p0, ..., pD) > 0, i.e.
//   det[p1 - p0, ..., pD - p0] > 0 (predicates.hpp; CGAL's sign).
//   opp[(D+1)c + i] = (D+1)c' + j when facet i of c is facet j of c' (the same
//   D vertices), or no_facet on the convex hull. Invariant: opp[opp[f]] == f.
//   Across a glued facet the two apexes lie on opposite sides: replacing
//   vertex i of c by the apex of c' gives a negatively oriented simplex.
//   A free slot has cell[(D+1)c] == no_vertex; free_slots lists them, and
//   the flip that needs a slot takes the last one freed (deterministic).
//
// Sizes: points #V; cell and opp (D+1) * slot_count(); free_slots <= slots.
// Nothing here depends on a kernel: geometry comes from predicates.hpp.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace ddt {
using index_t = std::int32_t;  // the same alias as mesh.hpp's
}

namespace ddt::core {

template <int D>
using Vec = std::array<double, D>;
template <int D>
using CellVertices = std::array<index_t, D + 1>;  // one cell's vertex ids
template <int D>
using FacetKey = std::array<index_t, D>;  // a facet's vertex ids, sorted

inline constexpr index_t no_facet = -1;
inline constexpr index_t no_vertex = -1;

template <int D>
constexpr index_t cell_of(index_t facet) {
  return facet / (D + 1);
}
template <int D>
constexpr int local_of(index_t facet) {
  return static_cast<int>(facet % (D + 1));
}

template <int D>
struct SimplexMesh {
  static_assert(D >= 1, "a simplex mesh has dimension 1 or more");
  static constexpr int cell_size = D + 1;

  std::vector<Vec<D>> points;       // #V vertex positions
  std::vector<index_t> cell;        // (D+1) * #slots vertex ids, positively oriented
  std::vector<index_t> opp;         // (D+1) * #slots glued facets, no_facet on the hull
  std::vector<index_t> free_slots;  // slots whose cell was removed

  index_t slot_count() const { return static_cast<index_t>(cell.size() / cell_size); }
  bool is_live(index_t c) const { return cell[cell_size * static_cast<std::size_t>(c)] != no_vertex; }
  index_t cell_count() const { return slot_count() - static_cast<index_t>(free_slots.size()); }
  index_t vertex(index_t c, int i) const { return cell[cell_size * static_cast<std::size_t>(c) + i]; }

  CellVertices<D> cell_vertices(index_t c) const {
    CellVertices<D> v;
    for (int i = 0; i <= D; ++i) v[i] = vertex(c, i);
    return v;
  }
  std::array<Vec<D>, D + 1> cell_points(index_t c) const {
    std::array<Vec<D>, D + 1> p;
    for (int i = 0; i <= D; ++i) p[i] = points[vertex(c, i)];
    return p;
  }
  // The vertex of c' across facet f (the apex of opp[f]); precondition: glued.
  index_t apex_across(index_t f) const { return cell[opp[f]]; }

  // Appends a cell with unglued facets and returns its slot.
  index_t add_cell(const CellVertices<D>& v) {
    const index_t c = slot_count();
    cell.insert(cell.end(), v.begin(), v.end());
    opp.insert(opp.end(), cell_size, no_facet);
    return c;
  }

  // Sets both directions of a glued pair so adjacency is never half-updated.
  void link(index_t f, index_t g) {
    opp[f] = g;
    if (g != no_facet) opp[g] = f;
  }
};

// Element-wise equality of two id arrays, written out so the flip loops
// compare a few integers inline instead of calling memcmp.
template <std::size_t N>
constexpr bool same_ids(const std::array<index_t, N>& x, const std::array<index_t, N>& y) {
  for (std::size_t i = 0; i < N; ++i)
    if (x[i] != y[i]) return false;
  return true;
}

// The sorted vertex ids of facet f (slot (D+1)c + i): the key two glued
// facets share.
template <int D>
FacetKey<D> facet_key(const SimplexMesh<D>& mesh, index_t f) {
  const index_t c = cell_of<D>(f);
  const int skip = local_of<D>(f);
  FacetKey<D> key;
  int n = 0;
  for (int i = 0; i <= D; ++i)
    if (i != skip) key[n++] = mesh.vertex(c, i);
  std::sort(key.begin(), key.end());
  return key;
}

// Signed content of a simplex in floating point: det[p1 - p0, ..., pD - p0]
// / D! (length, area, volume, ...), positive for positive orientation. The
// sign is exact only far from degeneracy: decide orientation with orient<D>.
template <int D>
double signed_content(const std::array<Vec<D>, D + 1>& p) {
  // Gaussian elimination with partial pivoting on the D x D edge matrix.
  std::array<std::array<double, D>, D> m;
  for (int r = 0; r < D; ++r)
    for (int k = 0; k < D; ++k) m[r][k] = p[r + 1][k] - p[0][k];
  double det = 1;
  for (int k = 0; k < D; ++k) {
    int pivot = k;
    for (int r = k + 1; r < D; ++r)
      if (std::abs(m[r][k]) > std::abs(m[pivot][k])) pivot = r;
    if (m[pivot][k] == 0) return 0;
    if (pivot != k) std::swap(m[pivot], m[k]), det = -det;
    det *= m[k][k];
    for (int r = k + 1; r < D; ++r) {
      const double factor = m[r][k] / m[k][k];
      for (int j = k; j < D; ++j) m[r][j] -= factor * m[k][j];
    }
  }
  double factorial = 1;
  for (int i = 2; i <= D; ++i) factorial *= i;
  return det / factorial;
}

// Sum of signed_content over the live cells.
template <int D>
double total_content(const SimplexMesh<D>& mesh) {
  double sum = 0;
  for (index_t c = 0; c < mesh.slot_count(); ++c)
    if (mesh.is_live(c)) sum += signed_content<D>(mesh.cell_points(c));
  return sum;
}

// Glues every facet of the live cells from scratch by matching facet keys
// (O(T log T)); facets matched by no other cell become hull facets. Returns
// false, leaving opp partly set, when three or more cells share a facet
// (the cells are no manifold). Geometry is not read: check_mesh<D> tells
// whether the result is a valid mesh.
template <int D>
bool link_facets(SimplexMesh<D>& mesh);

// Builds a mesh from points and cells listed in any orientation: each cell
// is made positive (two vertices swapped when orient<D> < 0; a degenerate
// cell is kept as given, for check_mesh to report), then link_facets.
template <int D>
SimplexMesh<D> mesh_from_cells(std::vector<Vec<D>> points, const std::vector<CellVertices<D>>& cells);

}  // namespace ddt::core
