#pragma once
// glibc's malloc tuned for the work's allocation pattern: bands of output
// rows (a few MB each, allocated and freed by the hundred) are served again
// from freed heap memory instead of fresh pages, which cost a page fault
// each (docs/performance.md). Process-wide: the command line calls it at
// start, the Python module when imported.

namespace ddt {

// M_MMAP_THRESHOLD 32 MB and M_TRIM_THRESHOLD 1 GB; without effect where
// the C library is not glibc.
void tune_allocator();

}  // namespace ddt
