#include "util/thread_limit.hpp"

#include <algorithm>
#include <thread>

namespace ddt {

int usable_threads(int requested) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::min(requested, cores);
}

std::unique_ptr<tbb::global_control> limit_threads(int requested) {
  if (requested <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, usable_threads(requested));
}

}  // namespace ddt
