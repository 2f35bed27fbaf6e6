#pragma once
// glibc's malloc tuned for the work's allocation pattern: buffers of output
// rows, residuals and meshes, allocated and freed by the band, are served
// again from freed heap memory instead of fresh pages, which cost a page
// fault each (docs/performance.md, "Freed memory reused"). Process-wide.

namespace ddt {

enum class AllocatorUse {
  // Bands of one size, one after another, in a process of their own (the
  // image command): every buffer comes from one heap shared by all threads,
  // and the heap is never trimmed, so each band reuses the pages of the one
  // before, and each stage those another thread freed.
  equal_bands,
  // Anything else (volumes, sequences, the Python module): blocks under
  // 32 MB from the heap, kept up to 1 GB free; larger ones mapped apart and
  // returned when freed, so buffers of changing sizes do not pile up.
  general,
};

// equal_bands: M_MMAP_MAX 0, M_TRIM_THRESHOLD -1, M_ARENA_MAX 1; general:
// M_MMAP_THRESHOLD 32 MB, M_TRIM_THRESHOLD 1 GB, M_MMAP_MAX glibc's
// default. Without effect where the C library is not glibc.
void tune_allocator(AllocatorUse use);

}  // namespace ddt
