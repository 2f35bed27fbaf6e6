#pragma once
// The generalized Lawson procedure of Tóth et al. on a tetrahedral mesh
// (optimizer.hpp's 3D twin), run by the dimension-independent driver of
// lawson.hpp with the bistellar flips of mesh3.hpp.
//
// Items (the paper's k-simplices, k = 1, 2) are named by slot: item
// 10 t + i (i < 4) is face i of tetrahedron t, tested for a 2-3 flip;
// item 10 t + 4 + k is local edge k of t, tested for 3-2, 4-4 and 2-2
// (the better of two 4-4 diagonals wins). A flip is taken when it lowers
// the weighted content by more than relative_tolerance times the local
// cost, so the total strictly decreases and the procedure terminates.
// After a flip, the faces and edges of the new tetrahedra go to the
// candidate list, and for facet costs (which read the gradients of
// neighbours) those of the tetrahedra around them too.
//
// The cost change of a flip is computed locally from the tetrahedra whose
// weight changes: the old and new tetrahedra and, for facet costs, the
// neighbours across the region's boundary faces; never by re-summing.
//
// Cost forms (costs.hpp; n = 3, content = volume):
//   simplex_weight          sum over tetrahedra of volume(T) * w(values at T's 4 vertices)
//   facet_weighted_content  sum over tetrahedra of volume(T) * mean over T's 4 faces of c(f),
//                           c = 0 on hull faces; evaluated as
//                           sum over interior faces of c(f) (volume(T1) + volume(T2)) / 4
//   facet_sum               sum over interior faces of c(f)
// Multi-channel values: the sum of the per-channel costs.
//
// Inputs:
//   mesh    valid Mesh3 (check_mesh3), modified in place
//   values  #V by K vertex values driving the cost (row-major)
//   K       1..max_cost_channels
//   cost    a CostFunction from costs.hpp
// Complexity: O(#faces + #edges) tests in the first iteration, then the
// candidates; each test O(K) with small constants.

#include "costs.hpp"
#include "mesh3.hpp"
#include "optimizer.hpp"  // max_cost_channels

#include <functional>
#include <string>
#include <vector>

namespace ddt {

struct FlipCounts {
  long long by_kind[flip_kind_count] = {0, 0, 0, 0};
  long long total() const;
  std::string summary() const;  // "2-3: 12, 3-2: 4, 4-4: 0, 2-2: 1"
};

struct Lawson3Options {
  double relative_tolerance = 1e-9;
  int max_iterations = 10000;
  // Called after each iteration with (iteration, flips in it, total cost now).
  std::function<void(int, const FlipCounts&, double)> on_iteration;
};

struct Lawson3Stats {
  int iterations = 0;
  FlipCounts flips;
  long long tests = 0;
  double cost_before = 0;
  double cost_after = 0;
};

// The total cost of the mesh, summed from scratch.
double total_cost(const Mesh3& mesh, const std::vector<float>& values, int K, const CostFunction& cost);

// Local cost of the region a flip changes, before and after (all other
// contributions are unchanged), and the scale of its rounding noise: for
// facet costs the sum of |g1| |g2| times the weight over the facet terms
// (c(f) cancels to ~0 when gradients agree, the noise does not), else 0.
// The rule the optimizer applies: improves(tol) is
//   gain > tol * max(before, after, noise_scale)  and  gain > 0,
// so a linear field (all gradients equal up to rounding) makes no flips.
struct LocalCosts {
  double before = 0;
  double after = 0;
  double noise_scale = 0;
  double gain() const { return before - after; }
  bool improves(double relative_tolerance) const;
};
// Precondition: plan valid on the mesh.
LocalCosts flip_costs(const Mesh3& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                      const FlipPlan& plan);

Lawson3Stats optimize_lawson(Mesh3& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                             const Lawson3Options& options = {});

}  // namespace ddt
