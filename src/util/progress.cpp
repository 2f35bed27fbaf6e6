#include "util/progress.hpp"

#include <algorithm>
#include <cstdio>
#include <unistd.h>

namespace ddt {

double Progress::Snapshot::fraction() const {
  if (total <= 0) return 0;
  return std::clamp(static_cast<double>(done) / static_cast<double>(total), 0.0, 1.0);
}

void Progress::begin(const std::string& stage, std::int64_t total) {
  stop_if_cancelled();
  std::lock_guard<std::mutex> lock(mutex_);
  stage_ = stage;
  total_.store(total, std::memory_order_relaxed);
  done_.store(0, std::memory_order_relaxed);
}

Progress::Snapshot Progress::snapshot() const {
  Snapshot s;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    s.stage = stage_;
  }
  s.total = total_.load(std::memory_order_relaxed);
  s.done = done_.load(std::memory_order_relaxed);
  return s;
}

ProgressBar::ProgressBar(const Progress& progress, std::FILE* out, Options options)
    : progress_(progress), out_(out), options_(std::move(options)), start_(std::chrono::steady_clock::now()) {
  thread_ = std::thread([this] { run(); });
}

ProgressBar::~ProgressBar() { stop(); }

bool ProgressBar::is_terminal(std::FILE* f) { return f && ::isatty(::fileno(f)) == 1; }

std::string ProgressBar::format(const Progress::Snapshot& s, double seconds, int width) {
  std::string line = s.stage.empty() ? std::string("working") : s.stage;
  line.resize(std::max<std::size_t>(line.size(), 11), ' ');
  char tail[64];
  if (s.total > 0) {
    const double f = s.fraction();
    const int full = static_cast<int>(f * width);
    std::string bar(static_cast<std::size_t>(width), ' ');
    for (int i = 0; i < full; ++i) bar[i] = '=';
    if (full < width) bar[full] = '>';
    std::snprintf(tail, sizeof tail, "] %3d%%  %.1f s", static_cast<int>(f * 100), seconds);
    line += " [" + bar + tail;
  } else {
    // Unknown total: a marker sweeping the bar.
    std::string bar(static_cast<std::size_t>(width), ' ');
    const int period = 2 * width - 2 > 0 ? 2 * width - 2 : 1;
    int k = static_cast<int>(seconds * 10) % period;
    if (k >= width) k = period - k;
    bar[std::clamp(k, 0, width - 1)] = '*';
    std::snprintf(tail, sizeof tail, "]       %.1f s", seconds);
    line += " [" + bar + tail;
  }
  return line;
}

void ProgressBar::draw_locked() {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string line = options_.prefix + format(progress_.snapshot(), seconds, options_.width);
  std::fprintf(out_, "\r%s\033[K", line.c_str());
  std::fflush(out_);
  drawn_ = true;
}

void ProgressBar::erase_locked() {
  if (!drawn_) return;
  std::fprintf(out_, "\r\033[K");
  std::fflush(out_);
  drawn_ = false;
}

void ProgressBar::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (wake_.wait_for(lock, options_.delay, [this] { return stopping_; })) return;
  while (!stopping_) {
    draw_locked();
    wake_.wait_for(lock, options_.period, [this] { return stopping_; });
  }
}

void ProgressBar::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  erase_locked();
}

void ProgressBar::print(const std::string& line) {
  std::lock_guard<std::mutex> lock(mutex_);
  erase_locked();
  std::fprintf(out_, "%s\n", line.c_str());
  std::fflush(out_);
}

}  // namespace ddt
