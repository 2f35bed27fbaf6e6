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
// neighbours across its four outer edges. It is taken by the core's rule
// (core/local_cost.hpp): when it lowers the total by more than
// relative_tolerance times the larger of the local cost and, for facet
// costs, the scale of its rounding noise; so the total strictly decreases,
// the procedure terminates, and --tolerance means what it means in 3D.
//
// Regions (large meshes, in parallel). Lawson's result depends on the order
// of the flips. A mesh of more than 2 * region_triangles triangles is cut
// into regions of region_triangles consecutive triangle ids (meshes from
// delaunay_triangulation list triangles by their smallest vertex, so on an
// image a region is a band of rows). Phase 0 runs the procedure above in
// every region at once; an edge whose test would touch a triangle of
// another region (its two triangles and their four neighbours) is deferred.
// Odd phases do the same on regions shifted by half a region, which hold
// the deferred edges of the even phases' seams in their interior, and so on
// until no edge is left; edges deferred by both partitions (triangles
// longer than half a region) end in one sequential phase. Each region is
// processed sequentially in a fixed order and only touches its own
// triangles, so the result is the same for any number of threads: it
// depends on the mesh, the values and region_triangles only. It differs
// from the single-region order by the order of flips near region seams
// (another local optimum, same criterion, same local optimality). Meshes up
// to 2 * region_triangles triangles run as one region: exactly the
// sequential procedure.
//
// Inputs:
//   mesh         valid Mesh2 (check_mesh), modified in place
//   values       #V by K vertex values driving the cost (row-major)
//   K            number of value channels, 1..max_cost_channels
//   cost         a CostFunction from costs.hpp
// Threads: the calling TBB arena (all cores unless limited by the caller).
// Complexity: O(#edges) per iteration; each test O(K).

#include "core/costs.hpp"
#include "core/local_cost.hpp"
#include "image/mesh.hpp"

#include <functional>
#include <vector>

namespace ddt {

struct LawsonOptions {
  double relative_tolerance = 1e-9;
  int max_iterations = 10000;
  // Triangles per region of the parallel schedule (see above). > 0:
  // regions of that size whatever the mesh size; 0: default_region_triangles
  // when the mesh has more than twice that, else one region; < 0: one region.
  long long region_triangles = 0;
  // A region boundary lies at this triangle id (and every region_triangles
  // from it): tiles of an image align their regions with the whole image's.
  long long region_origin = 0;
  // Specialized evaluators for the built-in costs (sederberg, sederberg-edge,
  // variance): the same arithmetic as flip_costs, so the same decisions, and
  // flat quadrilaterals (equal values at a, b, c, d) skipped, where these
  // costs are exactly 0 before and after. false: flip_costs for every test.
  bool fast_evaluation = true;
  // Called after each iteration (each phase when running in regions) with
  // (iteration, flips in it, total cost now).
  std::function<void(int, long long, double)> on_iteration;
  // Called now and then with the number of edge tests made so far, from
  // one thread at a time (maybe not the caller's); may be empty.
  std::function<void(long long)> on_tests;
};

inline constexpr long long default_region_triangles = 1 << 18;

// Regions for a pixel grid `width` samples wide: whole rows of cells (at
// least 64), about default_region_triangles triangles each, as upscale()
// uses them. Tools that rebuild upscale()'s mesh pass this.
long long image_region_triangles(int width);

struct LawsonStats {
  int iterations = 0;   // iterations (of the single region), or phases (regions)
  long long flips = 0;
  long long tests = 0;
  long long skipped_flat = 0;  // tests decided by the flat shortcut
  int regions = 1;             // regions of phase 0
  // The total cost before and after. The Sederberg fast path sums the terms
  // before as its regions first read them, and tracks the total after from
  // the flips' gains in the schedule's fixed order (so both may differ from
  // total_cost in the last bits); the other paths call total_cost.
  double cost_before = 0;
  double cost_after = 0;
};

// The total cost of the mesh, summed from scratch (in parallel, in fixed
// chunks summed in order: the same result for any number of threads).
double total_cost(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost);

// Local cost of the configuration around half-edge e before and after
// flipping it (other contributions are unchanged), with the noise scale of
// its facet terms: the core's LocalCosts, whose improves() is the one
// acceptance rule of every dimension. Precondition: e interior.
// The reference evaluation; the optimizer's fast paths reproduce it bit for bit.
using FlipCosts = core::LocalCosts;
FlipCosts flip_costs(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                     index_t e);

LawsonStats optimize_lawson(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                            const LawsonOptions& options = {});

}  // namespace ddt
