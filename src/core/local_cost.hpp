#pragma once
// ddt::core local costs — the cost of a SimplexMesh<D> (costs.hpp's three
// forms, n = D) summed from scratch, the change a flip makes to it computed
// from the cells it touches, and the one acceptance rule of the optimizer.
//
// Cost forms (content = length, area, volume, ...):
//   simplex_weight          sum over cells s of content(s) * w(values at s's D+1 vertices)
//   facet_weighted_content  sum over cells of content(s) * mean over s's D+1 facets of c(f),
//                           c = 0 on the hull; evaluated as
//                           sum over interior facets of c(f) (content(s1) + content(s2)) / (D+1)
//   facet_sum               sum over interior facets of c(f)
// Multi-channel values: the sum of the per-channel costs.
//
// A flip changes the weights of its removed and inserted cells and, for
// facet costs, the terms of the facets between them and the outside
// neighbours across the region's boundary; nothing else.

#include "core/flips.hpp"
#include "core/costs.hpp"

#include <algorithm>
#include <vector>

namespace ddt::core {

// Local cost of the region a flip changes, before and after, and the scale
// of its rounding noise: for facet costs the sum of |g1| |g2| times the
// weight over the facet terms (c(f) cancels to ~0 when gradients agree, the
// noise does not), else 0.
struct LocalCosts {
  double before = 0;
  double after = 0;
  double noise_scale = 0;
  double gain() const { return before - after; }
  // The acceptance rule: gain > relative_tolerance * max(before, after,
  // noise_scale) and gain > 0. So the total strictly decreases (Lawson's
  // procedure terminates), and a linear field, whose facet terms are
  // rounding noise, makes no flips. NaN never improves.
  bool improves(double relative_tolerance) const {
    const double g = gain();
    // Two-argument maxima (the same left-to-right choice as the list form,
    // which kept this test out of line in the optimizer's inner loop).
    return g > 0 && g > relative_tolerance * std::max(std::max(before, after), noise_scale);
  }
};

// values: #V by K (row-major), K in 1..max_cost_channels.
template <int D>
double total_cost(const SimplexMesh<D>& mesh, const float* values, int K, const CostFunction& cost);

// Precondition: plan came from propose_flip on this mesh (not yet applied).
template <int D>
LocalCosts flip_costs(const SimplexMesh<D>& mesh, const float* values, int K, const CostFunction& cost,
                      const FlipPlan<D>& plan);

// The simplex-weight form with the removed cells' costs given (cell_cost
// of each, in plan.removed order) and the inserted ones' written to
// inserted_costs: the same sums, bit for bit, as flip_costs, without
// recomputing cells the caller has seen. Precondition: cost.form ==
// CostForm::simplex_weight.
template <int D>
LocalCosts flip_costs(const SimplexMesh<D>& mesh, const float* values, int K, const CostFunction& cost,
                      const FlipPlan<D>& plan, const double* removed_costs, double* inserted_costs);

// content(s) * w(values at s's vertices), summed over the K channels' w:
// one cell's term of the simplex-weight form.
template <int D>
double cell_cost(const SimplexMesh<D>& mesh, const float* values, int K, const CostFunction& cost,
                 const CellVertices<D>& ids);

}  // namespace ddt::core
