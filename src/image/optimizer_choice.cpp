#include "image/optimizer_choice.hpp"

#include "image/lookahead.hpp"

#include <cstdio>

namespace ddt {

void check_optimizer(Optimizer optimizer, const AnnealOptions& anneal) {
  if (optimizer == Optimizer::anneal) check_anneal_options(anneal);
}

LawsonStats run_optimizer(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                          Optimizer optimizer, const AnnealOptions& anneal, const LawsonOptions& lawson,
                          const std::function<void(const std::string&)>& log) {
  check_optimizer(optimizer, anneal);
  if (optimizer == Optimizer::anneal) {
    AnnealOptions schedule = anneal;
    if (log)
      schedule.on_step = [&](int step, double temperature, long long flips, double total) {
        char line[160];
        std::snprintf(line, sizeof line, "anneal: step %d, T %.4g, %lld flips, cost %.9g", step, temperature,
                      flips, total);
        log(line);
      };
    const AnnealStats as = optimize_anneal(mesh, values, K, cost, schedule, lawson);
    LawsonStats ls = as.lawson;  // the final Lawson pass, with totals over the whole run
    ls.flips += as.accepted;
    ls.cost_before = as.cost_before;
    ls.cost_after = as.cost_after;
    return ls;
  }
  if (optimizer == Optimizer::lookahead) {
    const LookaheadStats la = optimize_lookahead(mesh, values, K, cost, lawson);
    LawsonStats ls = la.first_lawson;  // totals cover all passes and pairs
    ls.flips = la.lawson_flips + 2 * la.pairs;
    ls.cost_after = la.cost_after;
    if (log)
      log("lookahead: " + std::to_string(la.sweeps) + " sweeps, " + std::to_string(la.pairs) + " flip pairs, " +
          std::to_string(la.lawson_flips) + " single flips");
    return ls;
  }
  return optimize_lawson(mesh, values, K, cost, lawson);
}

}  // namespace ddt
