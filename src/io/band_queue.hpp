#pragma once
// BandQueue — bands of output rows encoded on a thread of their own, so
// that the encoding of one band overlaps the work on the next (the
// writers of image_formats.hpp). push() returns at once unless two bands
// already wait, so at most about three bands are held. The first encoding
// error is kept: later bands are dropped, and push() and finish() throw it.

#include "util/image.hpp"

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

namespace ddt {

// The order an output image takes its bands in (image_formats.hpp,
// OutputImage): top to bottom, each row once, `width` wide, `channels`
// channels; the one check both band writers make.
class BandOrder {
 public:
  BandOrder(std::string path, int width, int height, int channels);
  // Throws unless `rows` follow the rows taken so far (nor after
  // finish()); false for an empty band.
  bool take(const Image& rows, int first_row);
  // Throws unless every row was taken; false when finished before.
  bool finish();

 private:
  std::string path_;
  int width_, height_, channels_;
  int next_row_ = 0;
  bool finished_ = false;
};

class BandQueue {
 public:
  using Encode = std::function<void(const Image& rows, int first_row)>;
  explicit BandQueue(Encode encode);
  ~BandQueue();  // stops the thread; bands still waiting are dropped
  BandQueue(const BandQueue&) = delete;
  BandQueue& operator=(const BandQueue&) = delete;

  void push(Image rows, int first_row);
  // Waits until every band is encoded and stops the thread.
  void finish();

 private:
  void run();
  void stop();
  Encode encode_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::pair<Image, int>> queue_;
  bool closing_ = false;
  std::string error_;
  std::thread thread_;
};

}  // namespace ddt
