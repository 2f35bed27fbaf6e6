#include "util/thread_limit.hpp"

#include <tbb/task_arena.h>

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

int allowed_threads() {
  const std::size_t limit = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return static_cast<int>(
      std::max<std::size_t>(1, std::min<std::size_t>(tbb::this_task_arena::max_concurrency(), limit)));
}

}  // namespace ddt
