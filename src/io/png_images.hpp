#pragma once
// The file pipeline's input and output images (image_formats.hpp) for PNG
// through libpng alone (png_file.hpp), and a PNG's enlargement into EXR
// through OpenEXR alone (exr_file.hpp): what both definitions of
// image_formats.hpp's functions choose for a PNG they take.

#include "io/image_formats.hpp"
#include "io/png_file.hpp"

#include <functional>
#include <memory>
#include <string>

namespace ddt {

// A PNG written by bands, encoded on a thread of its own (band_queue.hpp),
// staged and renamed at finish() (safe_file.hpp). Requires png_writes().
std::unique_ptr<OutputImage> create_png_output(const std::string& path, int width, int height, int channels,
                                               SampleFormat source_format, const PngMetadata* metadata,
                                               const EncodeOptions& encode);

// A PNG read by rows. Its outputs that png_writes() or exr_writes() do not
// take go to `other` (the library: OpenImageIO's writer; the front:
// NeedsOpenImageIO), with the metadata already scaled.
class PngInputImage final : public InputImage {
 public:
  using OtherOutput = std::function<std::unique_ptr<OutputImage>(
      const std::string& path, int width, int height, const ImageHeader& source, const PngMetadata& metadata,
      const EncodeOptions& encode)>;
  PngInputImage(std::unique_ptr<PngReader> reader, OtherOutput other);

  const ImageHeader& header() const override { return reader_->header(); }
  int pages() const override { return 1; }
  void read(int first, int end, float* rows) override { reader_->read(first, end, rows); }
  std::unique_ptr<OutputImage> create_output(const std::string& path, int width, int height,
                                             const EncodeOptions& encode) override;

 private:
  std::unique_ptr<PngReader> reader_;
  OtherOutput other_;
};

}  // namespace ddt
