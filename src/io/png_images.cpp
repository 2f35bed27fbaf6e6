#include "io/png_images.hpp"

#include "io/band_queue.hpp"
#include "io/safe_file.hpp"

#include <optional>

namespace ddt {
namespace {

class PngOutputImage final : public OutputImage {
 public:
  PngOutputImage(const std::string& path, int width, int height, int channels, SampleFormat source_format,
                 const PngMetadata* metadata, const EncodeOptions& encode)
      : path_(path), width_(width), height_(height), channels_(channels), stage_(path) {
    name_ = stage_.target().filename().string();
    file_ = stage_.create(name_);
    writer_.emplace(stage_, file_, path, width, height, channels, source_format, metadata, encode);
    queue_.emplace([this](const Image& rows, int) { writer_->write(rows.pixels.data(), rows.height); });
  }

  void write(Image rows, int first_row) override {
    if (finished_ || rows.width != width_ || rows.channels != channels_ || first_row != next_row_ || rows.height < 0 ||
        first_row + rows.height > height_)
      throw Error("cannot write '" + path_ + "': band of rows " + std::to_string(first_row) + ".." +
                  std::to_string(first_row + rows.height) + " (" + std::to_string(rows.width) +
                  " wide) does not follow row " + std::to_string(next_row_) + " of a " + std::to_string(width_) +
                  "x" + std::to_string(height_) + " image");
    if (rows.height == 0) return;
    next_row_ += rows.height;
    queue_->push(std::move(rows), first_row);
  }

  void finish() override {
    if (finished_) return;
    if (next_row_ != height_)
      throw Error("cannot write '" + path_ + "': only " + std::to_string(next_row_) + " of " +
                  std::to_string(height_) + " rows were given");
    finished_ = true;
    queue_->finish();
    writer_->finish();
    stage_.finish(file_);  // throws with the first write error (ENOSPC, EFBIG, EIO)
    stage_.commit({name_});
  }

 private:
  std::string path_;
  int width_, height_, channels_;
  int next_row_ = 0;
  bool finished_ = false;
  // Destroyed in reverse: the encoding thread, the encoder, the staged file.
  StagedOutput stage_;
  std::string name_;
  int file_ = -1;
  std::optional<PngWriter> writer_;
  std::optional<BandQueue> queue_;
};

}  // namespace

std::unique_ptr<OutputImage> create_png_output(const std::string& path, int width, int height, int channels,
                                               SampleFormat source_format, const PngMetadata* metadata,
                                               const EncodeOptions& encode) {
  return std::make_unique<PngOutputImage>(path, width, height, channels, source_format, metadata, encode);
}

PngInputImage::PngInputImage(std::unique_ptr<PngReader> reader, OtherOutput other)
    : reader_(std::move(reader)), other_(std::move(other)) {}

std::unique_ptr<OutputImage> PngInputImage::create_output(const std::string& path, int width, int height,
                                                          const EncodeOptions& encode) {
  const ImageHeader& source = reader_->header();
  const PngMetadata metadata = scaled_png_metadata(reader_->metadata(), double(width) / source.width,
                                                   double(height) / source.height);
  if (png_writes(path, width, height, source.channels, encode))
    return create_png_output(path, width, height, source.channels, source.format, &metadata, encode);
  return other_(path, width, height, source, metadata, encode);
}

}  // namespace ddt
