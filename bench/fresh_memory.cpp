// How long the first write to fresh anonymous memory takes: in 4 KB pages
// faulted one by one ("small"), in transparent huge pages ("huge"), or in
// 4 KB pages mapped by MADV_POPULATE_WRITE first ("populate", as
// util/prefaulted_image.hpp maps them); on THREADS threads, each writing
// its share (docs/performance.md, "Memory pages", "Fresh memory on every
// thread").
//   g++ -O2 -pthread bench/fresh_memory.cpp -o /tmp/fresh_memory
//   for i in 1 2 3; do for m in small populate; do for t in 1 2; do /tmp/fresh_memory $m 64 $t; done; done; done
#include <sys/mman.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

int main(int argc, char** argv) {
  const std::string mode = argc >= 3 ? argv[1] : "";
  if ((argc != 3 && argc != 4) || (mode != "huge" && mode != "small" && mode != "populate")) {
    std::fprintf(stderr, "usage: fresh_memory huge|small|populate MEGABYTES [THREADS]\n");
    return 2;
  }
  const std::size_t two_mb = std::size_t(1) << 21;
  const std::size_t bytes = ((std::strtoull(argv[2], nullptr, 10) << 20) + two_mb - 1) / two_mb * two_mb;
  const int threads = argc == 4 ? std::max(1, std::atoi(argv[3])) : 1;
  const auto start = std::chrono::steady_clock::now();
  void* map = mmap(nullptr, bytes + two_mb, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED) {
    std::perror("mmap");
    return 1;
  }
  // Whole 2 MB blocks: huge pages need them, and the threads' shares are whole pages.
  char* data = reinterpret_cast<char*>((reinterpret_cast<std::uintptr_t>(map) + two_mb - 1) & ~(two_mb - 1));
  if (mode == "huge") madvise(data, bytes, MADV_HUGEPAGE);
  const std::size_t blocks = bytes / two_mb;
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t)
    workers.emplace_back([&, t] {
      char* from = data + blocks * t / threads * two_mb;
      const std::size_t share = (blocks * (t + 1) / threads - blocks * t / threads) * two_mb;
#ifdef MADV_POPULATE_WRITE
      if (mode == "populate") madvise(from, share, MADV_POPULATE_WRITE);
#endif
      std::memset(from, 1, share);
    });
  for (std::thread& worker : workers) worker.join();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s pages, %s MB, %d thread%s: %.3f s\n", mode.c_str(), argv[2], threads, threads == 1 ? "" : "s",
              seconds);
  munmap(map, bytes + two_mb);
}
