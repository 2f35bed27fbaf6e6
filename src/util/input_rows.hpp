#pragma once
// ddt::InputRows — an input image's rows as a pass down the image reads
// them (the streamed consistent reconstruction's wavefront and the meshes
// it makes by bands): the whole image, held by the caller, or a window of
// rows read from a RowSource as they are asked for and dropped once the
// pass has released them. What a streamed job holds of its input then
// depends on the width and the pass's reach, not on the image's height.
//
// Asking again for rows already released reads them again from the source
// (a RowSource may be read from the top again): slower, never wrong.

#include "util/image.hpp"

#include <functional>

namespace ddt {

// Rows [first, end) of an image of width x height x channels, into `rows`
// (width * channels floats a row). Called with increasing ranges, and
// again from the top for a second pass (or for rows a pass lost).
struct RowSource {
  int width = 0, height = 0, channels = 0;
  std::function<void(int first, int end, float* rows)> read;
};

class InputRows {
 public:
  // The whole image, read in place: `image` must outlive this.
  explicit InputRows(const Image& image);
  // Rows read from `source` as asked: it must outlive this.
  explicit InputRows(const RowSource& source);

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  // The whole image when it is held, else nullptr.
  const Image* whole() const { return whole_; }

  // An image holding at least the input's rows [first, end): its row i is
  // the input's row top + i (`top` set here). Code that clamps at its
  // borders asks for the rows its stencil reaches, so that it clamps only
  // where the input ends. Valid until the next call of rows().
  // Errors: throws ddt::Error for rows outside the image, and the source's.
  const Image& rows(int first, int end, int& top);
  // Rows before `row` are asked for no more (rows() may drop them).
  void release(int row);

  // The most rows held at once, and the rows read again after release.
  int peak_rows() const { return peak_rows_; }
  long long rows_read_again() const { return rows_read_again_; }

 private:
  const Image* whole_ = nullptr;
  const RowSource* source_ = nullptr;
  int width_ = 0, height_ = 0, channels_ = 0;
  Image window_;                     // rows [origin_, loaded_)
  int origin_ = 0, loaded_ = 0, released_ = 0;
  int peak_rows_ = 0;
  long long rows_read_again_ = 0;
};

}  // namespace ddt
