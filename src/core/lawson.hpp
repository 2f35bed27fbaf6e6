#pragma once
// ddt::core::optimize_lawson<D> — the generalized Lawson procedure of Tóth
// et al. (paper, Fig. 7) on a SimplexMesh<D>, with the parallel region
// schedule, for any D.
//
//   List_active    = every item (a k-simplex, 1 <= k <= D-1, whose removal
//                    may lower the cost)
//   while the last iteration lowered the cost:
//     for each item of List_active:
//       if a flip removing it lowers the cost (local_cost.hpp's rule):
//       apply it, and put every item whose local optimality it may have
//       changed on List_candidate (unless already on a list)
//     List_active = List_candidate, List_candidate = {}
//
// Items. Item (P c + j) of cell c is the simplex of its local vertices
// item_mask<D>(j): j in 0..D are the facets (facet j, tested for the flips
// that remove it: 2D 2-2, 3D 2-3), then the lower simplices with D-1 down
// to 2 vertices (3D: the 6 edges, tested for 3-2, 4-4 and 2-2). P =
// items_per_cell<D>. A facet is listed from the smaller of its two slots;
// a lower simplex first from the smallest slot of its star, after a flip
// from the first new cell holding it. When propose_flip offers two flips
// (the two diagonals of a degenerate star), the larger gain is taken.
// After a flip the items of the new cells go to the candidate list, and
// for facet costs (which read the neighbours' gradients) those of the
// cells around them too.
//
// The region schedule (large meshes, in parallel). Lawson's result depends
// on the order of the flips. A cell belongs to the band of its smallest
// vertex id: bands of region_vertices consecutive ids (grid and volume
// samples are numbered row by row, slice by slice, so a band is a slab).
// Phase 0 runs the procedure in every band at once; an item whose flip
// would read or write a cell of another band (its star, the cells around
// the star, the items it touches) is deferred. Odd phases do the same on
// bands shifted by half a band, which hold the previous seams inside, and
// so on until no item is left; items deferred by both partitions end in
// one sequential phase. New cells take their slots from a pool each band
// receives before a phase (free slots first, then fresh ones); a flip that
// would need more than its pool holds is deferred. Each band is processed
// sequentially in a fixed order, touches only its own cells and pool, and
// the results are merged in band order, so the output is the same for any
// number of threads: it depends on the mesh, the values and
// region_vertices only. It differs from the single-region order by the
// order of flips near the seams (another local optimum, same criterion).
// Meshes of at most 2 * default_region_cells cells run as one region:
// exactly the sequential procedure.
//
// Inputs:
//   mesh    valid SimplexMesh<D> (check_mesh<D>), modified in place
//   values  #V by K vertex values driving the cost (row-major)
//   K       1..max_cost_channels
//   cost    a CostFunction from costs.hpp
// Threads: the calling TBB arena.
// Errors: throws ddt::Error on a bad K or a values array of the wrong size.
// Complexity: O(#items) tests in the first iteration, then the candidates;
// each test O(K) with small constants (exact predicates).

#include "core/local_cost.hpp"

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace ddt::core {

// How many flips of each kind "removed-inserted" were applied.
struct FlipCounts {
  static constexpr int side = 17;  // up to max_flip_cells<4> cells a side
  int dimension = 0;               // D, for the kinds summary() always lists
  std::array<long long, side * side> by_kind{};
  void add(int removed, int inserted) { ++by_kind[removed * side + inserted]; }
  long long count(int removed, int inserted) const { return by_kind[removed * side + inserted]; }
  long long total() const;
  FlipCounts& operator+=(const FlipCounts& other);
  // "2-3: 12, 3-2: 4, 4-4: 100, 2-2: 0": the dimension's usual kinds (the
  // non-degenerate ones; in 3D also the lattice's 4-4 and hull 2-2), then
  // any other kind applied.
  std::string summary() const;
};

inline constexpr long long default_region_cells = 1 << 18;
// Each region of a parallel phase takes a pool of free slots for the cells
// its flips add: max(256, its share of the cells / pool_share) of them,
// fresh ones appended when the mesh has too few free. Room for the first
// phase's pools, for a mesh of `cells` to reserve when it is made (growing
// its arrays later would move them):
inline constexpr long long pool_share = 8;
inline std::size_t lawson_pool_room(std::size_t cells) { return cells / pool_share + 4096; }

struct LawsonOptions {
  double relative_tolerance = 1e-9;
  int max_iterations = 10000;
  // Vertex ids per band of the region schedule. > 0: bands of that size
  // whatever the mesh size; 0: bands of about default_region_cells cells
  // when the mesh has more than twice that, else one region; < 0: one region.
  long long region_vertices = 0;
  // After each iteration (each phase with regions): (iteration, flips in
  // it, total cost now, tracked from the gains).
  std::function<void(int, const FlipCounts&, double)> on_iteration;
  // When set, no flip removes a simplex (its `count` vertex ids) for which
  // this is true: a caller's knowledge the cost does not have (image
  // sequences' slow texture, volume/slow_texture.hpp). Called from the
  // schedule's threads: it must only read.
  std::function<bool(const index_t* vertices, int count)> kept_simplex;
};

struct LawsonStats {
  int iterations = 0;  // iterations of the single region, or phases
  FlipCounts flips;
  long long tests = 0;
  long long deferred = 0;  // tests handed to a later phase
  int regions = 1;         // bands of phase 0
  double cost_before = 0;
  double cost_after = 0;
};

template <int D>
LawsonStats optimize_lawson(SimplexMesh<D>& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                            const LawsonOptions& options = {});

}  // namespace ddt::core
