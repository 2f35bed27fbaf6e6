#include "util/prefaulted_image.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

namespace ddt {

void populate_pages([[maybe_unused]] const void* data, [[maybe_unused]] std::size_t bytes) {
#ifdef MADV_POPULATE_WRITE
  // Whole pages inside the buffer only; a failure (an older kernel) leaves
  // the pages to be faulted in as usual.
  const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + page - 1) / page * page, last = (begin + bytes) / page * page;
  if (page > 0 && last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_POPULATE_WRITE);
#endif
}

Image prefaulted_image(int width, int height, int channels) {
  Image image;
  image.width = width, image.height = height, image.channels = channels;
  image.pixels = prefaulted_zeros<float>(static_cast<std::size_t>(width) * height * channels);
  return image;
}

std::future<Image> prefaulted_image_async(int width, int height, int channels) {
  return std::async(std::launch::async, [=] { return prefaulted_image(width, height, channels); });
}

}  // namespace ddt
