#pragma once
// glibc's malloc tuned for the work's allocation pattern: buffers of output
// rows, residuals and meshes, allocated and freed by the band, are served
// again from freed heap memory instead of fresh pages, which cost a page
// fault each (docs/performance.md, "Memory pages"). Process-wide.

namespace ddt {

enum class AllocatorUse {
  // A process that is ours alone (the command line): every buffer comes
  // from the heap, and freed memory stays with the process for the next.
  own_process,
  // A process shared with other work (the Python module): buffers over
  // 32 MB are mapped apart and returned to the system when freed.
  shared_process,
};

// own_process: M_MMAP_MAX 0 (no buffer mapped apart) and no trimming of
// the heap (a band's buffers stay for the next); shared_process:
// M_MMAP_THRESHOLD 32 MB and M_TRIM_THRESHOLD 1 GB. Without effect where
// the C library is not glibc.
void tune_allocator(AllocatorUse use);

}  // namespace ddt
