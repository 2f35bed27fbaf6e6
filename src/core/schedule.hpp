#pragma once
// ddt::core schedule — the two loops of the generalized Lawson procedure
// (paper, Fig. 7) that every dimension shares: the iterations inside one
// region, and the phases of the parallel region schedule around them.
// core/lawson.cpp runs them on SimplexMesh<D> items; image/optimizer.cpp
// runs them on Mesh2 half-edges with its fast evaluators. What an item is,
// how a region is cut and how a test decides stay with the caller.
//
// Iterations (lawson_iterations). List_active is the initial scan (when
// `scan`: scan_initial(counts) tests every initially queued item of the
// region in its fixed order) or `active`; each test may push items on
// `candidate`; then List_active = List_candidate. Stops after an iteration
// without a flip, when no item is left, or after max_iterations (the items
// left over are handed to drop(item), which clears their pending flags).
//
// Phases (run_region_phases). Phase 0 runs every region of the even
// partition at once; odd phases the partition shifted by half a region, and
// so on while items are pending. Items deferred by both partitions (their
// star is longer than half a region) are left once two phases in a row
// made no flip, or after max_phases: then one phase runs them as a single
// region, sequentially. At most max_iterations phases.
//
// Both are templates over callbacks so the hot loops inline; neither reads
// a clock or a thread id, so the results depend on the callbacks only.

#include "core/simplex_mesh.hpp"

#include <vector>

namespace ddt::core {

// Flips in a count type: a plain number, or anything with total().
inline long long flip_total(long long flips) { return flips; }
template <class Counts>
long long flip_total(const Counts& flips) {
  return flips.total();
}

// scan_initial(Counts&), test(item, Counts&), drop(item),
// on_iteration(iteration, const Counts& flips in it); `make()` a zero Counts.
// iterations and total are the region's, updated in place.
template <class Counts, class Make, class ScanInitial, class Test, class Drop, class OnIteration>
void lawson_iterations(bool scan, std::vector<index_t> active, std::vector<index_t>& candidate, int max_iterations,
                       int& iterations, Counts& total, Make make, ScanInitial scan_initial, Test test, Drop drop,
                       OnIteration on_iteration) {
  while ((scan || !active.empty()) && iterations < max_iterations) {
    ++iterations;
    Counts now = make();
    if (scan) {
      scan_initial(now);
      scan = false;
    } else {
      for (index_t item : active) test(item, now);
    }
    total += now;
    active.swap(candidate);
    candidate.clear();
    on_iteration(iterations, now);
    if (flip_total(now) == 0) break;
  }
  for (index_t item : active) drop(item);  // left over at max_iterations: dropped, as in one region
}

inline constexpr int max_phases = 64;

// phase(index, single) runs one phase and returns its flip count;
// pending() says whether items are handed to the next phase. Returns the
// number of phases run.
template <class Phase, class Pending>
int run_region_phases(int max_iterations, Phase phase, Pending pending) {
  long long flips_last = -1, flips_before_last = -1;
  int phases = 0;
  for (int k = 0; k == 0 || pending(); ++k) {
    if (k >= max_iterations) break;
    const bool single = k >= 2 && ((flips_last == 0 && flips_before_last == 0) || k >= max_phases);
    const long long flips = phase(k, single);
    phases = k + 1;
    flips_before_last = flips_last;
    flips_last = flips;
  }
  return phases;
}

}  // namespace ddt::core
