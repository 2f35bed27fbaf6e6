#pragma once
// ddt::run_lawson — the generalized Lawson procedure of Tóth et al. (paper,
// Fig. 7) as a driver that knows no dimension and no kind of flip.
//
//   List_active    = every item (a k-simplex, 1 <= k <= n-1, whose removal
//                    may lower the cost: edges, faces, ...)
//   List_candidate = {}
//   while the last iteration lowered the cost:
//     for each item of List_active:
//       if a transformation removing it lowers the cost: apply it, and put
//       every item whose local optimality it may have changed on
//       List_candidate (unless already on a list)
//     List_active = List_candidate, List_candidate = {}
//
// The Problem decides what an item is and how to improve it:
//   index_t item_slots() const;
//       items are integers in [0, item_slots()); the range may grow
//   template <class Add> void initial_items(Add add) const;
//       calls add(item) for each item of the first List_active
//   template <class Touch> double improve(index_t item, double relative_tolerance, Touch touch);
//       tests the item; when a transformation lowers the cost by more
//       than relative_tolerance times the local cost (and by more than 0),
//       applies it, calls touch(j) for every item whose local optimality
//       it may have changed, and returns the decrease; else returns 0.
//       An item whose simplex no longer exists returns 0.
//   double total_cost() const;
//       summed from scratch; called before and after
// Items are deduplicated by a pending flag per item (on a list, not yet
// tested); when a problem names one simplex by several items, it picks one
// of them in touch() to keep duplicates rare (duplicates only cost tests).
//
// Each iteration lowers the cost strictly, the meshes are finitely many,
// so the procedure terminates; max_iterations is only a safety bound.
// Complexity: O(items tested) improve() calls.

#include "mesh.hpp"  // index_t

#include <vector>

namespace ddt {

struct LawsonRun {
  int iterations = 0;
  long long improvements = 0;  // transformations applied
  long long tests = 0;         // improve() calls
  double cost_before = 0;
  double cost_after = 0;
};

// on_iteration(iteration, improvements in it, total cost now) after each
// iteration; the total is tracked from the returned decreases.
template <class Problem, class OnIteration>
LawsonRun run_lawson(Problem& problem, double relative_tolerance, int max_iterations, OnIteration on_iteration) {
  LawsonRun run;
  run.cost_before = problem.total_cost();
  double cost_now = run.cost_before;
  std::vector<char> pending(problem.item_slots(), 0);
  std::vector<index_t> active, candidate;
  problem.initial_items([&](index_t item) {
    if (pending[item]) return;
    pending[item] = 1;
    active.push_back(item);
  });
  auto touch = [&](index_t item) {
    if (static_cast<std::size_t>(item) >= pending.size()) pending.resize(problem.item_slots(), 0);
    if (pending[item]) return;
    pending[item] = 1;
    candidate.push_back(item);
  };
  while (!active.empty() && run.iterations < max_iterations) {
    ++run.iterations;
    long long improvements_now = 0;
    for (index_t item : active) {
      pending[item] = 0;
      ++run.tests;
      const double gain = problem.improve(item, relative_tolerance, touch);
      if (gain > 0) {
        cost_now -= gain;
        ++improvements_now;
      }
    }
    run.improvements += improvements_now;
    active.swap(candidate);
    candidate.clear();
    on_iteration(run.iterations, improvements_now, cost_now);
    if (improvements_now == 0) break;
  }
  run.cost_after = problem.total_cost();
  return run;
}

}  // namespace ddt
