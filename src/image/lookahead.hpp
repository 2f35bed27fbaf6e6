#pragma once
// ddt::optimize_lookahead — Lawson's procedure with a two-flip look-ahead
// move: a flip that raises the cost is kept when a flip of one of the four
// edges it leaves around its quadrilateral then lowers the total by more
// (the optional move of issue 6; the paper names look-ahead as another
// optimizer the weighted content admits, Sect. 4).
//
// Algorithm:
//   optimize_lawson                                     (a local optimum)
//   repeat until a sweep keeps no pair, at most max_sweeps times:
//     for each interior edge e (in slot order), if flippable:
//       g1 = gain of flipping e (<= 0 at a Lawson optimum); flip e
//       for each outer edge h of the new quadrilateral (c-a, a-d, d-b, b-c),
//       if flippable: g2 = gain of flipping h now
//       keep the best pair when g1 + g2 > relative_tolerance * (local cost
//       before both flips, or the two flips' noise scales summed if larger:
//       core/local_cost.hpp) and > 0: flip h; else flip e back
//     if the sweep kept a pair: optimize_lawson again
// Every kept pair and every Lawson flip lowers the total strictly, so it
// terminates; the result is locally optimal for single flips (it ends with
// Lawson) and for these pairs. Deterministic.
//
// Inputs and errors as optimize_lawson (optimizer.hpp); `lawson` is passed
// to every Lawson pass. Complexity per sweep: about 5 flip_costs per edge.

#include "core/costs.hpp"
#include "image/mesh.hpp"
#include "image/optimizer.hpp"

#include <vector>

namespace ddt {

struct LookaheadOptions {
  int max_sweeps = 100;  // safety bound on pair sweeps
};

struct LookaheadStats {
  int sweeps = 0;              // pair sweeps made
  long long pairs = 0;         // flip pairs kept (2 flips each)
  long long lawson_flips = 0;  // single flips over all Lawson passes
  LawsonStats first_lawson;    // the first pass: plain Lawson's result
  double cost_before = 0, cost_after = 0;
};

LookaheadStats optimize_lookahead(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                                  const LawsonOptions& lawson = {}, const LookaheadOptions& options = {});

}  // namespace ddt
