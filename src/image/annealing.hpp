#pragma once
// ddt::optimize_anneal — simulated annealing over the same edge flips and
// costs as the generalized Lawson procedure (optimizer.hpp), the stochastic
// alternative the paper compares it with (Tóth et al., Sect. 5 and Fig. 8;
// DDT by annealing after L. L. Schumaker, "Computing optimal triangulations
// using simulated annealing", CAGD 10 (1993), and O. Kreylos, B. Hamann,
// IEEE TVCG 7 (2001)).
//
// Algorithm (Metropolis et al. 1953; Kirkpatrick et al. 1983):
//   T = T0
//   repeat temperature_steps times:
//     repeat moves_per_edge * #interior edges times:
//       pick an interior edge e uniformly at random
//       if e is flippable (strictly convex quadrilateral):
//         delta = cost after flipping e - cost before (flip_costs, local)
//         flip when delta <= 0, else with probability exp(-delta / T)
//     T = cooling * T                                  (geometric cooling)
//   optimize_lawson                       (final descent to a local optimum)
// T0 (automatic unless given) accepts the mean cost increase of the uphill
// flips of a random sample of edges with probability initial_acceptance
// (Kirkpatrick's rule): T0 = mean(delta > 0) / -ln(initial_acceptance).
// The defaults end at T = T0 * 0.9^49 ~ T0 / 175.
//
// Determinism: the moves depend only on `seed` (std::mt19937_64, whose
// output the standard fixes; no std:: distributions), so a run is
// reproducible across platforms for the same mesh, values and options.
//
// Inputs:
//   mesh      valid Mesh2 (check_mesh), modified in place
//   values    #V by K vertex values driving the cost (row-major)
//   K         number of value channels, 1..max_cost_channels
//   cost      a CostFunction from costs.hpp
//   options   schedule and seed; lawson: options of the final Lawson pass
// Errors: throws ddt::Error for K out of range or options out of range.
// Complexity: O(temperature_steps * moves_per_edge * #edges) cost
// evaluations of O(K) each, plus the Lawson pass.

#include "core/costs.hpp"
#include "ddtscale/options.hpp"
#include "image/mesh.hpp"
#include "image/optimizer.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ddt {

struct AnnealStats {
  double initial_temperature = 0, final_temperature = 0;
  int temperature_steps = 0;
  long long proposals = 0;       // interior edges drawn
  long long flippable = 0;       // ... of them with a strictly convex quadrilateral
  long long accepted = 0;        // flips made while annealing
  long long uphill = 0;          // ... of them raising the cost
  double cost_before = 0;        // total cost of the input mesh
  double cost_annealed = 0;      // total after annealing, before the Lawson pass
  double cost_after = 0;         // total at the end
  LawsonStats lawson;            // the final pass (zeros when skipped)
};

// Throws ddt::Error naming the first option out of range.
void check_anneal_options(const AnnealOptions& options);

// Automatic T0 for `mesh`: the mean cost increase of the uphill flips among
// up to `samples` random interior edges, divided by -ln(acceptance); 0 when
// the sample holds no uphill flip.
double initial_temperature(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                           double acceptance, std::uint64_t seed, int samples = 2000);

AnnealStats optimize_anneal(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                            const AnnealOptions& options = {}, const LawsonOptions& lawson = {});

}  // namespace ddt
