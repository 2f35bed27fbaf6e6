#include "util/allocator_tuning.hpp"

#include <doctest/doctest.h>

#include <cstdlib>

// glibc's malloc only: AddressSanitizer replaces it (and ignores mallopt).
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#include <malloc.h>

namespace {

// Whether a block of this size is mapped apart (mallinfo2's count of mapped
// blocks grows while it is held) rather than served from the heap.
bool mapped_apart(std::size_t bytes) {
  const std::size_t before = mallinfo2().hblks;
  void* block = std::malloc(bytes);
  REQUIRE(block != nullptr);
  const bool mapped = mallinfo2().hblks > before;
  std::free(block);
  return mapped;
}

}  // namespace

// The general case first: a block freed on the heap would serve the next.
TEST_CASE("tune_allocator: equal bands keep every buffer on the heap, the general setting maps large ones") {
  ddt::tune_allocator(ddt::AllocatorUse::general);
  CHECK_FALSE(mapped_apart(std::size_t(16) << 20));  // under the 32 MB threshold (glibc's own starts at 128 KB)
  CHECK(mapped_apart(std::size_t(64) << 20));
  ddt::tune_allocator(ddt::AllocatorUse::equal_bands);
  CHECK_FALSE(mapped_apart(std::size_t(16) << 20));
  CHECK_FALSE(mapped_apart(std::size_t(64) << 20));
  ddt::tune_allocator(ddt::AllocatorUse::general);  // as the other tests found it
}
#endif
