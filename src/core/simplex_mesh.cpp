#include "core/simplex_mesh.hpp"

#include "core/predicates.hpp"

#include <algorithm>
#include <utility>

namespace ddt::core {

template <int D>
bool link_facets(SimplexMesh<D>& mesh) {
  struct Entry {
    FacetKey<D> key;
    index_t facet;
  };
  std::vector<Entry> entries;
  entries.reserve(mesh.cell.size());
  for (index_t c = 0; c < mesh.slot_count(); ++c) {
    if (!mesh.is_live(c)) continue;
    for (int i = 0; i <= D; ++i) {
      const index_t f = (D + 1) * c + i;
      mesh.opp[f] = no_facet;
      entries.push_back({facet_key(mesh, f), f});
    }
  }
  // Ties by facet id keep the result independent of the sort's stability.
  std::sort(entries.begin(), entries.end(),
            [](const Entry& x, const Entry& y) { return x.key != y.key ? x.key < y.key : x.facet < y.facet; });
  for (std::size_t n = 0; n < entries.size();) {
    std::size_t end = n + 1;
    while (end < entries.size() && entries[end].key == entries[n].key) ++end;
    if (end - n > 2) return false;
    if (end - n == 2) mesh.link(entries[n].facet, entries[n + 1].facet);
    n = end;
  }
  return true;
}

template <int D>
SimplexMesh<D> mesh_from_cells(std::vector<Vec<D>> points, const std::vector<CellVertices<D>>& cells) {
  SimplexMesh<D> mesh;
  mesh.points = std::move(points);
  for (CellVertices<D> v : cells) {
    if (orient_ids<D>(mesh.points, v) < 0) std::swap(v[0], v[1]);
    mesh.add_cell(v);
  }
  link_facets(mesh);
  return mesh;
}

#define DDT_CORE_INSTANTIATE(D)                  \
  template bool link_facets<D>(SimplexMesh<D>&); \
  template SimplexMesh<D> mesh_from_cells<D>(std::vector<Vec<D>>, const std::vector<CellVertices<D>>&);
DDT_CORE_INSTANTIATE(1)
DDT_CORE_INSTANTIATE(2)
DDT_CORE_INSTANTIATE(3)
DDT_CORE_INSTANTIATE(4)
#undef DDT_CORE_INSTANTIATE

}  // namespace ddt::core
