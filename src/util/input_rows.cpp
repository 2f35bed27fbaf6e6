#include "util/input_rows.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <string>

namespace ddt {

namespace {

// Rows read from the source at a time, at the least: fewer calls into the
// decoder, a few rows more held.
constexpr int read_ahead_rows = 32;

}  // namespace

InputRows::InputRows(const Image& image)
    : whole_(&image), width_(image.width), height_(image.height), channels_(image.channels) {
  peak_rows_ = height_;
}

InputRows::InputRows(const RowSource& source)
    : source_(&source), width_(source.width), height_(source.height), channels_(source.channels) {
  window_ = Image(width_, 0, channels_);
}

const Image& InputRows::rows(int first, int end, int& top) {
  if (first < 0 || end > height_ || first >= end)
    throw Error("input rows " + std::to_string(first) + ".." + std::to_string(end) + " are not in an image of " +
                std::to_string(height_) + " rows");
  if (whole_) {
    top = 0;
    return *whole_;
  }
  const std::size_t row_floats = static_cast<std::size_t>(width_) * channels_;
  if (first < origin_) {  // released rows asked for again: read them from the source
    rows_read_again_ += std::min(end, origin_) - first;
    origin_ = loaded_ = first;
    window_.height = 0;
    window_.pixels.clear();
  }
  if (end > loaded_) {
    // Rows before both `first` and the released ones make room.
    const int keep = std::max(origin_, std::min(first, released_));
    const int target = std::min(height_, std::max(end, loaded_ + read_ahead_rows));
    std::copy(window_.pixels.begin() + static_cast<std::ptrdiff_t>(row_floats * (keep - origin_)),
              window_.pixels.end(), window_.pixels.begin());
    window_.height = target - keep;
    window_.pixels.reserve(row_floats * window_.height);  // no more than asked for: the vector would double
    window_.pixels.resize(row_floats * window_.height);
    source_->read(loaded_, target, window_.pixels.data() + row_floats * (loaded_ - keep));
    origin_ = keep;
    loaded_ = target;
    peak_rows_ = std::max(peak_rows_, window_.height);
  }
  top = origin_;
  return window_;
}

void InputRows::release(int row) { released_ = std::max(released_, std::min(row, height_)); }

}  // namespace ddt
