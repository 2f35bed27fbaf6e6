#pragma once
// Transparent huge pages for large buffers.
//
// A fresh 4 KB page costs a fault on first touch; on the virtual machines
// ddtscale is benchmarked on, about 12 microseconds each (0.6 s to zero a
// 200 MB output image, 0.02 s with 2 MB pages; docs/performance.md). Where
// the kernel grants huge pages only on request (transparent_hugepage =
// madvise, Debian's default), large buffers ask for them before they are
// first touched. Elsewhere the advice is harmless.

#include <cstddef>
#include <vector>

namespace ddt {

// Asks for huge pages on the 2 MB-aligned part of [data, data + bytes);
// does nothing below a few megabytes.
void advise_huge_pages(void* data, std::size_t bytes);

// v resized to n copies of value, its storage advised before it is touched.
template <class T>
void assign_huge(std::vector<T>& v, std::size_t n, const T& value) {
  std::vector<T>().swap(v);
  v.reserve(n);
  advise_huge_pages(v.data(), n * sizeof(T));
  v.resize(n, value);
}

}  // namespace ddt
