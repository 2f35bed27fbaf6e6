#include "io/png_images.hpp"

#include "io/band_queue.hpp"
#include "io/exr_file.hpp"
#include "io/safe_file.hpp"

#include <optional>

namespace ddt {
namespace {

class PngOutputImage final : public OutputImage {
 public:
  PngOutputImage(const std::string& path, int width, int height, int channels, SampleFormat source_format,
                 const PngMetadata* metadata, const EncodeOptions& encode)
      : order_(path, width, height, channels), stage_(path) {
    name_ = stage_.target().filename().string();
    file_ = stage_.create(name_);
    writer_.emplace(stage_, file_, path, width, height, channels, source_format, metadata, encode);
    queue_.emplace([this](const Image& rows, int) { writer_->write(rows.pixels.data(), rows.height); });
  }

  void write(Image rows, int first_row) override {
    if (order_.take(rows, first_row)) queue_->push(std::move(rows), first_row);
  }

  void finish() override {
    if (!order_.finish()) return;
    queue_->finish();
    writer_->finish();
    stage_.finish(file_);  // throws with the first write error (ENOSPC, EFBIG, EIO)
    stage_.commit({name_});
  }

 private:
  BandOrder order_;
  // Destroyed in reverse: the encoding thread, the encoder, the staged file.
  StagedOutput stage_;
  std::string name_;
  int file_ = -1;
  std::optional<PngWriter> writer_;
  std::optional<BandQueue> queue_;
};

class ExrOutputImage final : public OutputImage {
 public:
  ExrOutputImage(const std::string& path, int width, int height, int channels, int alpha_channel,
                 SampleFormat source_format, const ExrMetadata& metadata, const EncodeOptions& encode)
      : order_(path, width, height, channels), stage_(path) {
    name_ = stage_.target().filename().string();
    file_ = stage_.create(name_);
    writer_.emplace(stage_, file_, path, width, height, channels, alpha_channel, source_format, metadata, encode);
    queue_.emplace([this](const Image& rows, int) { writer_->write(rows.pixels.data(), rows.height); });
  }

  void write(Image rows, int first_row) override {
    if (order_.take(rows, first_row)) queue_->push(std::move(rows), first_row);
  }

  void finish() override {
    if (!order_.finish()) return;
    queue_->finish();
    writer_->finish();
    stage_.finish(file_);
    stage_.commit({name_});
  }

 private:
  BandOrder order_;
  StagedOutput stage_;
  std::string name_;
  int file_ = -1;
  std::optional<ExrWriter> writer_;
  std::optional<BandQueue> queue_;
};

// A PNG's metadata as OpenImageIO's EXR writer takes it from OpenImageIO's
// PNG reader (the library's as_attributes); the ICC profile it drops.
ExrMetadata exr_metadata(const PngMetadata& png) {
  ExrMetadata exr;
  exr.date_time = png.date_time;
  exr.has_resolution = png.has_resolution;
  exr.resolution_unit = png.per_inch ? "inch" : "none";
  exr.x_resolution = png.x_resolution, exr.y_resolution = png.y_resolution;
  exr.text = png.text;
  return exr;
}

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
  const ExrMetadata exr = exr_metadata(metadata);
  if (exr_writes(path, width, height, source.channels, source.format, exr, encode))
    return std::make_unique<ExrOutputImage>(path, width, height, source.channels, source.alpha_channel, source.format,
                                            exr, encode);
  return other_(path, width, height, source, metadata, encode);
}

}  // namespace ddt
