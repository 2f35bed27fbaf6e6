#pragma once
// The generalized Lawson procedure of Tóth et al. (paper, Fig. 7) on a 2D
// mesh: edges are tested from an active list; a flip is applied when it
// lowers the weighted-content cost; the edges whose local optimality the
// flip may change go to a candidate list, which becomes the next
// iteration's active list. Iterations stop when one makes no flip (the
// total cost did not decrease) or after max_iterations.
//
// A flip's cost change is computed locally from the simplices whose weight
// it changes: the quadrilateral's two triangles and, for facet costs, the
// neighbours across its four outer edges. It is taken only when it lowers
// the total by more than relative_tolerance times the local cost, so the
// total strictly decreases and the procedure terminates.
//
// Inputs:
//   mesh         valid Mesh2 (check_mesh), modified in place
//   values       #V by K vertex values driving the cost (row-major)
//   K            number of value channels, 1..max_cost_channels
//   cost         a CostFunction from costs.hpp
// Complexity: O(#edges) per iteration; each test O(K).

#include "costs.hpp"
#include "mesh.hpp"

#include <functional>
#include <vector>

namespace ddt {

inline constexpr int max_cost_channels = 8;

struct LawsonOptions {
  double relative_tolerance = 1e-9;
  int max_iterations = 10000;
  // Called after each iteration with (iteration, flips in it, total cost now).
  std::function<void(int, long long, double)> on_iteration;
};

struct LawsonStats {
  int iterations = 0;
  long long flips = 0;
  long long tests = 0;
  double cost_before = 0;
  double cost_after = 0;
};

// The total cost of the mesh, summed from scratch.
double total_cost(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost);

// Local cost of the configuration around half-edge e before and after
// flipping it (other contributions are unchanged). Precondition: e interior.
struct FlipCosts {
  double before = 0;
  double after = 0;
  double gain() const { return before - after; }
};
FlipCosts flip_costs(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                     index_t e);

LawsonStats optimize_lawson(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                            const LawsonOptions& options = {});

}  // namespace ddt
