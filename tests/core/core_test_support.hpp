#pragma once
// Helpers shared by the core tests: the dimension tags for
// TEST_CASE_TEMPLATE, point sets, and meshes compared as sets of cells.

#include "core/flips.hpp"
#include "core/simplex_mesh.hpp"

#include <algorithm>
#include <bit>
#include <random>
#include <set>
#include <type_traits>
#include <vector>

namespace ddt::core::test {

template <int D>
using Dim = std::integral_constant<int, D>;

// The unit simplex 0, e1, ..., eD (positively oriented in this order).
template <int D>
std::array<Vec<D>, D + 1> unit_simplex() {
  std::array<Vec<D>, D + 1> p{};
  for (int i = 1; i <= D; ++i) p[i][i - 1] = 1;
  return p;
}

// n uniform points in [0, 1)^D from a fixed seed (distinct, in general
// position with probability 1).
template <int D>
std::vector<Vec<D>> random_points(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec<D>> points(n);
  for (auto& p : points)
    for (double& x : p) x = unit(rng);
  return points;
}

// The points of an n^D lattice (integer coordinates, x fastest): the
// degenerate case (cospherical cells, coplanar circuits).
template <int D>
std::vector<Vec<D>> grid_points(int n) {
  std::vector<Vec<D>> points;
  int total = 1;
  for (int k = 0; k < D; ++k) total *= n;
  for (int id = 0; id < total; ++id) {
    Vec<D> p;
    for (int k = 0, rest = id; k < D; ++k, rest /= n) p[k] = rest % n;
    points.push_back(p);
  }
  return points;
}

// The live cells as sorted vertex tuples (check_mesh fixes each one's
// orientation, so the set determines the mesh up to slots).
template <int D>
std::set<CellVertices<D>> cell_set(const SimplexMesh<D>& mesh) {
  std::set<CellVertices<D>> cells;
  for (index_t c = 0; c < mesh.slot_count(); ++c) {
    if (!mesh.is_live(c)) continue;
    CellVertices<D> v = mesh.cell_vertices(c);
    std::sort(v.begin(), v.end());
    cells.insert(v);
  }
  return cells;
}

template <int D>
std::vector<index_t> sorted_ids(const std::array<index_t, D + 1>& ids, int count) {
  std::vector<index_t> s(ids.begin(), ids.begin() + count);
  std::sort(s.begin(), s.end());
  return s;
}

// The local mask of the vertex ids `ids` (all in cell c).
template <int D>
unsigned mask_of(const SimplexMesh<D>& mesh, index_t c, const std::vector<index_t>& ids) {
  unsigned mask = 0;
  for (int i = 0; i <= D; ++i)
    if (std::find(ids.begin(), ids.end(), mesh.vertex(c, i)) != ids.end()) mask |= 1u << i;
  return mask;
}

// The first live cell containing all of `ids`, or -1.
template <int D>
index_t cell_containing(const SimplexMesh<D>& mesh, const std::vector<index_t>& ids) {
  for (index_t c = 0; c < mesh.slot_count(); ++c)
    if (mesh.is_live(c) && std::popcount(mask_of(mesh, c, ids)) == static_cast<int>(ids.size())) return c;
  return -1;
}

// The flips removing conv(ids) in the mesh.
template <int D>
std::vector<FlipPlan<D>> flips_removing(const SimplexMesh<D>& mesh, const std::vector<index_t>& ids) {
  const index_t c = cell_containing(mesh, ids);
  if (c < 0) return {};
  FlipPlan<D> plans[4];
  const int n = propose_flip<D>(mesh, c, mask_of(mesh, c, ids), plans, 4);
  return std::vector<FlipPlan<D>>(plans, plans + n);
}

// The inverse of an applied plan: the flip removing conv B whose B is the
// old A. Returns false when propose_flip does not offer it.
template <int D>
bool inverse_flip(const SimplexMesh<D>& mesh, const FlipPlan<D>& applied, FlipPlan<D>& inverse) {
  const std::vector<index_t> b = sorted_ids<D>(applied.b, applied.b_count);
  const std::vector<index_t> a = sorted_ids<D>(applied.a, applied.a_count);
  for (const FlipPlan<D>& plan : flips_removing(mesh, b))
    if (sorted_ids<D>(plan.b, plan.b_count) == a) {
      inverse = plan;
      return true;
    }
  return false;
}

}  // namespace ddt::core::test
