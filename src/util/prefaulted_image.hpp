#pragma once
// ddt::prefaulted_image — a large image whose pages the kernel maps in one
// system call (MADV_POPULATE_WRITE) before its zeros are written, instead
// of taking a page fault per 4 KB page as they are first touched
// (docs/performance.md, "Memory pages"). Where the kernel lacks the
// advice, an ordinary allocation.
//
// prefaulted_image_async does it on a thread of its own, so that a caller
// can allocate its output while it triangulates; get() on the future waits
// and rethrows std::bad_alloc.

#include "util/image.hpp"

#include <future>

namespace ddt {

Image prefaulted_image(int width, int height, int channels);
std::future<Image> prefaulted_image_async(int width, int height, int channels);

}  // namespace ddt
