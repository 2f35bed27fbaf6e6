#pragma once
// ddt::chunked_sum — a parallel sum whose result does not depend on the
// number of threads: fixed chunks summed in parallel (TBB), the partial sums
// added in order.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ddt {

// Sum of term(i) for i in [0, items).
template <class Index, class Term>
double chunked_sum(Index items, Term term) {
  constexpr Index chunk = 1 << 15;
  std::vector<double> partial((static_cast<std::size_t>(items) + chunk - 1) / chunk, 0.0);
  tbb::parallel_for(std::size_t(0), partial.size(), [&](std::size_t k) {
    const Index lo = static_cast<Index>(k) * chunk, hi = std::min(items, static_cast<Index>(lo + chunk));
    double sum = 0;
    for (Index i = lo; i < hi; ++i) sum += term(i);
    partial[k] = sum;
  });
  double total = 0;
  for (double p : partial) total += p;
  return total;
}

}  // namespace ddt
