#pragma once
// ddt::run_optimizer — the mesh optimizer a user picks by name, for every
// pipeline that flips a 2D mesh (images, scattered points):
//   lawson     the generalized Lawson procedure (optimizer.hpp)
//   anneal     simulated annealing, then Lawson (annealing.hpp)
//   lookahead  Lawson plus two-flip moves (lookahead.hpp)
// (ddtscale/options.hpp names them.)
//
// Errors: throws ddt::Error for a bad schedule.

#include "ddtscale/options.hpp"
#include "image/annealing.hpp"
#include "core/costs.hpp"
#include "image/mesh.hpp"
#include "image/optimizer.hpp"

#include <functional>
#include <string>
#include <vector>

namespace ddt {

// Runs `optimizer` on the mesh with the Lawson settings `lawson` (and the
// schedule `anneal` for anneal); verbose lines go to `log` (may be
// empty). The statistics cover the whole run: flips of every pass, the cost
// before the first and after the last.
LawsonStats run_optimizer(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                          Optimizer optimizer, const AnnealOptions& anneal, const LawsonOptions& lawson,
                          const std::function<void(const std::string&)>& log = {});

// Throws ddt::Error unless, for anneal, the schedule is valid: the check to
// run before any long work.
void check_optimizer(Optimizer optimizer, const AnnealOptions& anneal);

}  // namespace ddt
