#pragma once
// The --threads / threads= option of the command line and the Python
// module: 0 means every core, and more threads than cores are not used
// (each thread holds its own buffers and only slows the work down).

#include <tbb/global_control.h>

#include <memory>

namespace ddt {

// requested capped at the machine's cores; <= 0 is returned unchanged.
int usable_threads(int requested);

// A limit on TBB's parallelism while the returned object lives; null (no
// limit) when requested <= 0.
std::unique_ptr<tbb::global_control> limit_threads(int requested);

// The threads a parallel loop may use here and now: the arena's
// concurrency, capped by an active limit_threads (a global_control, which
// the arena's concurrency does not show). At least 1.
int allowed_threads();

}  // namespace ddt
