#include "io/band_queue.hpp"

#include "util/error.hpp"

#include <exception>

namespace ddt {

BandQueue::BandQueue(Encode encode) : encode_(std::move(encode)), thread_([this] { run(); }) {}

BandQueue::~BandQueue() { stop(); }

void BandQueue::stop() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void BandQueue::run() {
  for (;;) {
    std::pair<Image, int> band;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return !queue_.empty() || closing_; });
      if (queue_.empty()) return;
      band = std::move(queue_.front());
      queue_.pop_front();
      if (!error_.empty()) {  // after a failure the rest is dropped
        changed_.notify_all();
        continue;
      }
    }
    changed_.notify_all();
    std::string failure;
    try {
      encode_(band.first, band.second);
    } catch (const std::exception& e) {
      failure = e.what();
    }
    if (!failure.empty()) {
      const std::lock_guard<std::mutex> lock(mutex_);
      error_ = failure;
      changed_.notify_all();
    }
  }
}

void BandQueue::push(Image rows, int first_row) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return queue_.size() < 2 || !error_.empty(); });
  if (!error_.empty()) throw Error(error_);
  queue_.emplace_back(std::move(rows), first_row);
  lock.unlock();
  changed_.notify_all();
}

void BandQueue::finish() {
  stop();
  if (!error_.empty()) throw Error(error_);
}

}  // namespace ddt
