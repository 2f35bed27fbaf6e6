#include "io/band_queue.hpp"

#include "util/error.hpp"

#include <exception>

namespace ddt {

BandOrder::BandOrder(std::string path, int width, int height, int channels)
    : path_(std::move(path)), width_(width), height_(height), channels_(channels) {}

bool BandOrder::take(const Image& rows, int first_row) {
  if (finished_ || rows.width != width_ || rows.channels != channels_ || first_row != next_row_ || rows.height < 0 ||
      first_row + rows.height > height_)
    throw Error("cannot write '" + path_ + "': band of rows " + std::to_string(first_row) + ".." +
                std::to_string(first_row + rows.height) + " (" + std::to_string(rows.width) +
                " wide) does not follow row " + std::to_string(next_row_) + " of a " + std::to_string(width_) + "x" +
                std::to_string(height_) + " image");
  next_row_ += rows.height;
  return rows.height > 0;
}

bool BandOrder::finish() {
  if (finished_) return false;
  if (next_row_ != height_)
    throw Error("cannot write '" + path_ + "': only " + std::to_string(next_row_) + " of " + std::to_string(height_) +
                " rows were given");
  finished_ = true;
  return true;
}

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
