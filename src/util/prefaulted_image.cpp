#include "util/prefaulted_image.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace ddt {

void populate_pages(void* data, std::size_t bytes) {
  // Whole pages inside the buffer only; without the advice (an older
  // kernel) the zeros written fault the pages in, still on every thread.
  const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  if (page == 0 || bytes == 0) return;
  const std::uintptr_t first = (begin + page - 1) / page * page, last = (begin + bytes) / page * page;
  if (last <= first) return;
  constexpr std::uintptr_t block = std::uintptr_t(1) << 21;
  const std::size_t blocks = (last - first + block - 1) / block;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, blocks, 1),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t b = range.begin(); b < range.end(); ++b) {
          const std::uintptr_t from = first + b * block, to = std::min(last, from + block);
          auto* p = reinterpret_cast<unsigned char*>(from);
#ifdef MADV_POPULATE_WRITE
          ::madvise(p, to - from, MADV_POPULATE_WRITE);
#endif
          std::memset(p, 0, to - from);
        }
      },
      tbb::simple_partitioner());
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
