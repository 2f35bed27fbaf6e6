#pragma once
// ddt::core flips — the bistellar flips of a SimplexMesh<D> for any D, read
// off the Radon partition of D + 2 points (the paper's Sect. 4 and Fig. 5),
// and the relinking that applies them.
//
// The non-degenerate flip. D + 2 points S in general position have one
// affine dependence; its signs split S into Radon's partition (A, B)
// (predicates.hpp, radon_partition). S has exactly two triangulations,
//   T_B = {S \ b : b in B}  (every cell contains conv A)  and
//   T_A = {S \ a : a in A}  (every cell contains conv B),
// and the flip replaces one by the other: |B| cells by |A| cells, the face
// conv A by conv B. Only |A|, |B| >= 2 keep the vertex set (|A| = 1 would
// delete a vertex), so the kinds are (removed - inserted):
//   2D: 2-2 (an edge for the other diagonal);
//   3D: 2-3 (a triangle for an edge), 3-2;
//   4D: 2-4 (a tetrahedron for an edge), 3-3 (a triangle for a triangle), 4-2.
//
//     2D, A = {a0, a2}, B = {b1, b3}         3D, A = {a, b, c}, B = {d, e}
//           b3                                        d
//          /  \                                      /|\        .
//        a0----a2    <->    a0  |  a2               a-+-c  <->  3 cells
//          \  /                 b1..b3 edge          \b/       around d-e
//           b1                                        e
//
// The degenerate flip (the lower-dimensional flip joined with its link).
// When the dependence of S vanishes on some points, the circuit A u B
// (|A| + |B| = k + 2 points) spans only a k-flat, k < D, and the cells
// present around conv A are (A u B \ b) u L: the k-dimensional flip's cells
// joined with each simplex L of a link complex (D - k vertices each,
// affinely independent of the flat). The flip replaces, for every L at
// once, T_B * L by T_A * L: |B| |Links| cells by |A| |Links|. The region
// of each L is conv(A u B) * L either way, so the region and its boundary
// are kept; the facets conv(A u B \ x) * (L minus a vertex) where two links
// meet are re-split on both sides alike, and on the hull they stay on the
// hull. Examples:
//   3D 4-4: the 2D 2-2 of a, b, w0, w2 (coplanar) joined with {w1}, {w3};
//   3D 2-2: the same with one link vertex {w1}: the hull case;
//   4D: a 2-2 in a plane joined with a cycle of m edges (2m-2m), a 2-3 or
//       3-2 in a 3-flat joined with two vertices (4-6, 6-4) or one (hull).
// No geometric test beyond the circuit's signs is needed: (A, B) is the
// Radon partition of A u B, so every new cell (A u B \ a) u L is
// non-degenerate, and the join structure makes the old and new cells
// triangulate the same region.

#include "core/simplex_mesh.hpp"

#include <array>
#include <string>

namespace ddt::core {

// The most cells a flip removes or inserts (and the largest star of a
// simplex that is searched): D + 1 suffices without degeneracy; the rest is
// room for links.
template <int D>
inline constexpr int max_flip_cells = 4 * D;

// The cells a caller may read: c when owner[c] == region (the parallel
// schedule gives each region the cells it owns; core/lawson.hpp).
struct ReadScope {
  const std::int32_t* owner = nullptr;
  std::int32_t region = 0;
  bool reads(index_t c) const { return owner[c] == region; }
};

// How propose_flip reads the mesh. scope: the cells it may read (null: all).
// lattice_exact: the points satisfy predicates.hpp's lattice_exact, so
// orientations are plain determinants (the same signs, faster).
struct ProposalOptions {
  const ReadScope* scope = nullptr;
  bool lattice_exact = false;
};

// A flip ready to apply: the cells it removes (slots) and the positively
// oriented cells it inserts, with the circuit that defines it.
template <int D>
struct FlipPlan {
  int a_count = 0, b_count = 0;
  std::array<index_t, D + 1> a{};  // conv A, a face of every removed cell
  std::array<index_t, D + 1> b{};  // conv B, a face of every inserted cell
  int link_count = 0;              // simplices in the link; 1 (the empty one) when not degenerate
  // Only the first removed_count / inserted_count entries are set: the
  // arrays are left unfilled because the optimizer builds a plan per test.
  int removed_count = 0;
  std::array<index_t, max_flip_cells<D>> removed;
  int inserted_count = 0;
  // Grouped by link: (A u B \ a[j]) u L_l at l * a_count + j, which
  // apply_flip reads to pair the new cells' facets without a search.
  std::array<CellVertices<D>, max_flip_cells<D>> inserted;
  // With ProposalOptions::lattice_exact the inserted cells' contents come
  // from the orientation tests, exact, so the same numbers simplex_content
  // gives and the costs need not compute them again.
  bool contents_known = false;
  std::array<double, max_flip_cells<D>> inserted_content;

  int circuit_dimension() const { return a_count + b_count - 2; }
  bool degenerate() const { return circuit_dimension() < D; }
};

// "removed-inserted", e.g. "2-3", "4-4", "6-6".
template <int D>
std::string flip_name(const FlipPlan<D>& plan);

// Every flip that removes the simplex conv A, given as the local vertices
// `simplex_mask` (bit i: vertex i) of cell `start`: a facet (D bits), an
// edge (2 bits), or anything between. Gathers the cells containing A (at
// most max_flip_cells<D>, else none), takes the Radon partition of the
// start cell plus each apex across a facet containing A, and keeps each
// partition with A as one side whose other side B makes the gathered cells
// exactly {(A u B \ b) u L}. Writes up to max_plans plans (several only for
// degenerate stars, e.g. an octahedron's two 4-4 diagonals) and returns
// how many. Exact (predicates.hpp). Preconditions: check_mesh<D> is "";
// start is live; simplex_mask has 2 .. D bits (others give 0 plans).
// Complexity: O(max_flip_cells (D + 2)) orientation tests.
// With options.scope, returns -1, having read nothing outside it, when the
// flip would need other cells.
template <int D>
int propose_flip(const SimplexMesh<D>& mesh, index_t start, unsigned simplex_mask, FlipPlan<D>* plans, int max_plans,
                 const ProposalOptions& options = {});

// Whether `start` is the smallest slot of the star of the simplex given by
// `simplex_mask` (every cell containing its vertices, found across the
// facets that contain them) and that star has at most max_flip_cells<D>
// cells. The walk stops at the first smaller slot.
template <int D>
bool first_of_star(const SimplexMesh<D>& mesh, index_t start, unsigned simplex_mask);

// Replaces plan.removed by plan.inserted and relinks every facet by its
// key: inside the region among the new cells, on its boundary to the old
// outside neighbours, hull facets unlinked. Reuses the removed slots first, then free slots (last freed first),
// then appends. Writes the new cells' slots to new_slots when given.
// free_slots (optional) replaces mesh.free_slots as the list slots are taken
// from and freed to (a region's own pool in the parallel schedule; when it
// holds inserted_count - removed_count slots or more, the arrays do not
// grow). Relinks only; precondition: the plan came from propose_flip on
// this mesh.
template <int D>
void apply_flip(SimplexMesh<D>& mesh, const FlipPlan<D>& plan, index_t* new_slots = nullptr,
                std::vector<index_t>* free_slots = nullptr);

}  // namespace ddt::core
