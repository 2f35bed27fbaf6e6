#include "util/allocator_tuning.hpp"

#include <cstddef>  // any C library header: it is what defines __GLIBC__

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace ddt {

void tune_allocator(AllocatorUse use) {
#if defined(__GLIBC__)
  const bool equal_bands = use == AllocatorUse::equal_bands;
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, equal_bands ? -1 : 1 << 30);  // -1: never
  mallopt(M_MMAP_MAX, equal_bands ? 0 : 65536);           // 65536: glibc's default
  // One arena: what the optimizer's worker threads free serves the main
  // thread's render buffers next, instead of fresh pages beside them.
  if (equal_bands) mallopt(M_ARENA_MAX, 1);
#else
  (void)use;
#endif
}

}  // namespace ddt
