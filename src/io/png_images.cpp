#include "io/png_images.hpp"

#include "io/band_queue.hpp"
#include "io/exr_file.hpp"
#include "io/safe_file.hpp"

#include <optional>
#include <utility>

namespace ddt {
namespace {

// An image encoded by `Encoder` (PngWriter, ExrWriter: constructed from
// the staged file, the path, the size and the encoder's own arguments)
// into a staged file, each band on the encoding thread.
template <class Encoder>
class StagedBandOutput final : public OutputImage {
 public:
  template <class... EncoderArguments>
  StagedBandOutput(const std::string& path, int width, int height, int channels, EncoderArguments&&... arguments)
      : order_(path, width, height, channels), stage_(path) {
    name_ = stage_.target().filename().string();
    file_ = stage_.create(name_);
    encoder_.emplace(stage_, file_, path, width, height, channels, std::forward<EncoderArguments>(arguments)...);
    queue_.emplace([this](const Image& rows, int) { encoder_->write(rows.pixels.data(), rows.height); });
  }

  void write(Image rows, int first_row) override {
    if (order_.take(rows, first_row)) queue_->push(std::move(rows), first_row);
  }

  void finish() override {
    if (!order_.finish()) return;
    queue_->finish();
    encoder_->finish();
    stage_.finish(file_);  // throws with the first write error (ENOSPC, EFBIG, EIO)
    stage_.commit({name_});
  }

 private:
  BandOrder order_;
  // Destroyed in reverse: the encoding thread, the encoder, the staged file.
  StagedOutput stage_;
  std::string name_;
  int file_ = -1;
  std::optional<Encoder> encoder_;
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
  return std::make_unique<StagedBandOutput<PngWriter>>(path, width, height, channels, source_format, metadata,
                                                       encode);
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
    return std::make_unique<StagedBandOutput<ExrWriter>>(path, width, height, source.channels, source.alpha_channel,
                                                         source.format, exr, encode);
  return other_(path, width, height, source, metadata, encode);
}

}  // namespace ddt
