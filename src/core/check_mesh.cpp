#include "core/check_mesh.hpp"

#include "core/predicates.hpp"

#include <algorithm>
#include <map>
#include <sstream>

namespace ddt::core {
namespace {

// Euler characteristic of the complex of the live cells and all their faces.
template <int D>
long long euler_characteristic(const SimplexMesh<D>& mesh) {
  // faces[k]: the (k+1)-vertex faces, sorted ids padded with no_vertex.
  std::array<std::vector<CellVertices<D>>, D + 1> faces;
  for (index_t c = 0; c < mesh.slot_count(); ++c) {
    if (!mesh.is_live(c)) continue;
    CellVertices<D> v = mesh.cell_vertices(c);
    std::sort(v.begin(), v.end());
    for (unsigned mask = 1; mask < (1u << (D + 1)); ++mask) {
      CellVertices<D> face;
      face.fill(no_vertex);
      int n = 0;
      for (int i = 0; i <= D; ++i)
        if (mask & (1u << i)) face[n++] = v[i];
      faces[n - 1].push_back(face);
    }
  }
  long long chi = 0;
  for (int k = 0; k <= D; ++k) {
    auto& list = faces[k];
    std::sort(list.begin(), list.end());
    const long long count = std::unique(list.begin(), list.end()) - list.begin();
    chi += (k % 2 == 0) ? count : -count;
  }
  return chi;
}

}  // namespace

template <int D>
std::string check_mesh(const SimplexMesh<D>& mesh) {
  std::ostringstream problem;
  if (mesh.cell.size() % (D + 1) != 0 || mesh.opp.size() != mesh.cell.size()) return "array sizes disagree";
  const index_t slots = mesh.slot_count();
  const index_t n_points = static_cast<index_t>(mesh.points.size());
  std::vector<char> listed_free(slots, 0);
  for (index_t c : mesh.free_slots) {
    if (c < 0 || c >= slots || mesh.is_live(c) || listed_free[c]) {
      problem << "free slot list names slot " << c << " wrongly";
      return problem.str();
    }
    listed_free[c] = 1;
  }
  std::map<std::array<index_t, D - 1>, int> hull_ridges;
  bool any_live = false;
  for (index_t c = 0; c < slots; ++c) {
    if (!mesh.is_live(c)) {
      if (!listed_free[c]) {
        problem << "slot " << c << " is free but not in free_slots";
        return problem.str();
      }
      continue;
    }
    any_live = true;
    const CellVertices<D> v = mesh.cell_vertices(c);
    for (int i = 0; i <= D; ++i) {
      if (v[i] < 0 || v[i] >= n_points) {
        problem << "cell " << c << " has vertex " << v[i] << " out of range";
        return problem.str();
      }
      for (int j = 0; j < i; ++j)
        if (v[i] == v[j]) {
          problem << "cell " << c << " repeats vertex " << v[i];
          return problem.str();
        }
    }
    if (orient_ids<D>(mesh.points, v) <= 0) {
      problem << "cell " << c << " is not strictly positively oriented";
      return problem.str();
    }
    for (int i = 0; i <= D; ++i) {
      const index_t f = (D + 1) * c + i, g = mesh.opp[f];
      if (g == no_facet) {
        const FacetKey<D> key = facet_key(mesh, f);
        for (int skip = 0; skip < D; ++skip) {
          std::array<index_t, D - 1> ridge;
          for (int k = 0, n = 0; k < D; ++k)
            if (k != skip) ridge[n++] = key[k];
          ++hull_ridges[ridge];
        }
        continue;
      }
      if (g < 0 || g >= (D + 1) * slots || !mesh.is_live(cell_of<D>(g)) || mesh.opp[g] != f) {
        problem << "facet " << f << " (cell " << c << ") is not glued symmetrically";
        return problem.str();
      }
      if (cell_of<D>(g) == c || facet_key(mesh, f) != facet_key(mesh, g)) {
        problem << "facet " << f << " and its twin " << g << " have different vertices";
        return problem.str();
      }
      CellVertices<D> swapped = v;
      swapped[i] = mesh.apex_across(f);
      if (orient_ids<D>(mesh.points, swapped) >= 0) {
        problem << "cells " << c << " and " << cell_of<D>(g) << " lie on the same side of their facet";
        return problem.str();
      }
    }
  }
  for (const auto& [ridge, count] : hull_ridges)
    if (count != 2) {
      problem << "a hull ridge (first vertex " << ridge[0] << ") is in " << count << " hull facets, not 2";
      return problem.str();
    }
  if (!any_live) return {};
  const long long chi = euler_characteristic(mesh);
  if (chi != 1) {
    problem << "Euler characteristic " << chi << ", not 1 (the cells are no ball)";
    return problem.str();
  }
  return {};
}

template <int D>
bool is_delaunay(const SimplexMesh<D>& mesh) {
  for (index_t c = 0; c < mesh.slot_count(); ++c) {
    if (!mesh.is_live(c)) continue;
    const auto p = mesh.cell_points(c);
    for (int i = 0; i <= D; ++i) {
      const index_t g = mesh.opp[(D + 1) * c + i];
      if (g != no_facet && in_sphere<D>(p, mesh.points[mesh.apex_across((D + 1) * c + i)]) > 0) return false;
    }
  }
  return true;
}

#define DDT_CORE_INSTANTIATE(D)                              \
  template std::string check_mesh<D>(const SimplexMesh<D>&); \
  template bool is_delaunay<D>(const SimplexMesh<D>&);
DDT_CORE_INSTANTIATE(2)
DDT_CORE_INSTANTIATE(3)
DDT_CORE_INSTANTIATE(4)
#undef DDT_CORE_INSTANTIATE

}  // namespace ddt::core
