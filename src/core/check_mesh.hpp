#pragma once
// ddt::core::check_mesh<D> — the validity check of a SimplexMesh<D>
// (2D's check_mesh and the former check_mesh3 in one), and is_delaunay<D>.
//
// check_mesh<D> checks, in this order, and names the first problem:
//   sizes      cell and opp hold (D+1) * slots entries;
//   free list  free_slots names exactly the free slots, each once;
//   cells      every live cell has D+1 distinct vertex ids in range and is
//              strictly positively oriented (orient<D> > 0, exact);
//   twins      opp[opp[f]] == f, the glued facet lies in another live cell,
//              has the same D vertices, and the two apexes lie on opposite
//              sides (vertex i replaced by the other apex orients < 0);
//   hull       the hull facets close up: every (D-2)-face of a hull facet is
//              in exactly two hull facets;
//   Euler      sum over k of (-1)^k (number of k-faces) == 1, a ball's
//              characteristic (V - E + F = 1 in 2D, V - E + F - T = 1 in 3D).
// Returns "" when valid. A mesh without cells is valid.
// Complexity: O(T 2^(D+1) log T) (the Euler count enumerates every face).
//
// is_delaunay<D>: no apex across an interior facet lies strictly inside a
// cell's circumsphere (in_sphere<D>, exact); local Delaunay everywhere
// implies global Delaunay. Precondition: check_mesh<D> is "".

#include "core/simplex_mesh.hpp"

#include <string>

namespace ddt::core {

template <int D>
std::string check_mesh(const SimplexMesh<D>& mesh);

template <int D>
bool is_delaunay(const SimplexMesh<D>& mesh);

}  // namespace ddt::core
