#pragma once
// ImageBandWriter — an output image written by bands of rows as they are
// made, so the whole image is never held (the streaming pipeline,
// pipeline/upscale.hpp UpscaleOptions::output_rows).
//
// The file is the one write_image(path, whole image, ...) writes, bit for
// bit: the same spec (sample type, encoding, metadata), the same pixels, fed
// to OpenImageIO's ImageOutput by scanlines (write_scanlines) or, for a
// tiled output (EncodeOptions::tile), by rows of tiles (write_tiles).
// Encoding runs on a thread of its own: write() queues a band and returns
// at once unless two bands already wait, so the encoding of one band
// overlaps the work on the next, and at most about three bands are held.
// The file is staged and renamed only by finish() (safe_file.hpp); a writer
// destroyed without finish() leaves the target untouched.
//
// Formats that do not encode row by row (GIF, WebP, ...), outputs whose
// EXIF orientation is applied to the pixels (PNG of a portrait photograph)
// and plugins without IOProxy support are written whole at finish(): the
// bands are then gathered (streaming() is false).
//
// Errors: ddt::Error with a one-line message, from the constructor (the
// spec or the encoding options do not suit the format, the target is not
// writable), from write() (the first encoding or write error, such as a
// full disk, as soon as it is seen) or from finish().

#include "io/encode_options.hpp"
#include "io/image_formats.hpp"
#include "io/image_io.hpp"

#include <memory>
#include <string>

namespace ddt {

class ImageBandWriter final : public OutputImage {
 public:
  ImageBandWriter(const std::string& path, int width, int height, int channels, SampleFormat source_format,
                  int alpha_channel = -1, const OIIO::ParamValueList* metadata = nullptr,
                  const EncodeOptions& encode = {});
  ~ImageBandWriter() override;
  ImageBandWriter(const ImageBandWriter&) = delete;
  ImageBandWriter& operator=(const ImageBandWriter&) = delete;

  // Rows [first_row, first_row + rows.height) of the image, `width` wide,
  // `channels` channels; bands come top to bottom, each row once
  // (first_row is the row after the last one written). Throws otherwise.
  void write(Image rows, int first_row) override;
  // Waits for the encoding, closes and renames the file over the target.
  // Every row must have been written.
  void finish() override;

  bool streaming() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace ddt
