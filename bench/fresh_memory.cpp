// How long the first touch of fresh anonymous memory takes, in 4 KB pages
// or in transparent huge pages (docs/performance.md, "Memory pages").
//   g++ -O2 bench/fresh_memory.cpp -o /tmp/fresh_memory
//   for i in 1 2 3; do /tmp/fresh_memory huge 700; /tmp/fresh_memory small 700; done
#include <sys/mman.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

int main(int argc, char** argv) {
  if (argc != 3 || (std::string(argv[1]) != "huge" && std::string(argv[1]) != "small")) {
    std::fprintf(stderr, "usage: fresh_memory huge|small MEGABYTES\n");
    return 2;
  }
  const bool huge = std::string(argv[1]) == "huge";
  const std::size_t bytes = std::strtoull(argv[2], nullptr, 10) << 20, two_mb = std::size_t(1) << 21;
  const auto start = std::chrono::steady_clock::now();
  void* map = mmap(nullptr, bytes + two_mb, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED) {
    std::perror("mmap");
    return 1;
  }
  char* data = static_cast<char*>(map);
  if (huge) {
    const auto aligned = (reinterpret_cast<std::uintptr_t>(data) + two_mb - 1) & ~(two_mb - 1);
    madvise(reinterpret_cast<void*>(aligned), bytes - two_mb, MADV_HUGEPAGE);
  }
  std::memset(data, 1, bytes);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s pages, %s MB: %.3f s\n", argv[1], argv[2], seconds);
  munmap(map, bytes + two_mb);
}
