#pragma once
// ddt::prefaulted_image — a large image whose pages the kernel maps in one
// system call per block (MADV_POPULATE_WRITE) before its zeros are written,
// instead of taking a page fault per 4 KB page as they are first touched,
// the blocks shared among the threads: on a virtual machine the first write
// to fresh memory is the expensive part (docs/performance.md, "Memory
// pages", "Fresh memory on every thread"). Where the kernel lacks the
// advice, the pages are only written first on every thread.
//
// prefaulted_image_async does it on a thread of its own, so that a caller
// can allocate its output while it triangulates; get() on the future waits
// and rethrows std::bad_alloc.

#include "util/image.hpp"

#include <cstddef>
#include <future>
#include <vector>

namespace ddt {

// Maps the whole pages of [data, data + bytes) and writes zeros into them,
// blocks of them on every thread of the caller's arena: storage not yet
// holding objects (a vector's capacity beyond its size).
void populate_pages(void* data, std::size_t bytes);

// Reserves n elements (and `spare` more, unmapped, for the vector to grow
// into), maps and first writes the n's pages on every thread, then
// value-initializes them (zeros written again, into pages already there).
template <class T>
std::vector<T> prefaulted_zeros(std::size_t n, std::size_t spare = 0) {
  std::vector<T> v;
  v.reserve(n + spare);
  populate_pages(v.data(), n * sizeof(T));
  v.resize(n);
  return v;
}

// v.resize(n, value), with the pages it grows into mapped in one call
// first, as above: within its capacity the new tail's, else a larger
// block's, into which v moves.
template <class T>
void prefaulted_resize(std::vector<T>& v, std::size_t n, const T& value) {
  if (n > v.capacity()) {
    std::vector<T> moved;
    moved.reserve(n);
    populate_pages(moved.data(), n * sizeof(T));
    moved.assign(v.begin(), v.end());
    v.swap(moved);
  } else if (n > v.size()) {
    populate_pages(v.data() + v.size(), (n - v.size()) * sizeof(T));
  }
  v.resize(n, value);
}

Image prefaulted_image(int width, int height, int channels);
std::future<Image> prefaulted_image_async(int width, int height, int channels);

}  // namespace ddt
