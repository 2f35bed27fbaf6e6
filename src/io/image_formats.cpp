// The library's image formats (image_formats.hpp): PNG through libpng
// where png_file.hpp takes the file, everything else through OpenImageIO.

#include "io/image_formats.hpp"

#include "io/band_writer.hpp"
#include "io/image_io.hpp"
#include "io/png_images.hpp"

#include <OpenImageIO/imageio.h>

namespace ddt {
namespace {

// A PNG's metadata as OpenImageIO's PNG reader gives it, in its order.
OIIO::ParamValueList as_attributes(const PngMetadata& metadata) {
  OIIO::ParamValueList list;
  if (!metadata.icc_profile.empty())
    list.attribute("ICCProfile", OIIO::TypeDesc(OIIO::TypeDesc::UINT8, int(metadata.icc_profile.size())),
                   metadata.icc_profile.data());
  if (!metadata.date_time.empty()) list.attribute("DateTime", metadata.date_time);
  for (const auto& [name, value] : metadata.text) list.attribute(name, value);
  if (metadata.has_resolution) {
    list.attribute("ResolutionUnit", metadata.per_inch ? "inch" : "none");
    list.attribute("XResolution", metadata.x_resolution);
    list.attribute("YResolution", metadata.y_resolution);
  }
  return list;
}

class OiioInputImage final : public InputImage {
 public:
  OiioInputImage(const std::string& path, const ImageReadLimits& limits) : reader_(path, limits) {}
  const ImageHeader& header() const override { return reader_.header(); }
  int pages() const override { return reader_.file().pages; }
  void read(int first, int end, float* rows) override { reader_.read(first, end, rows); }
  std::unique_ptr<OutputImage> create_output(const std::string& path, int width, int height,
                                             const EncodeOptions& encode) override {
    const ImageHeader& h = reader_.header();
    const OIIO::ParamValueList metadata =
        scaled_metadata(reader_.file().metadata, double(width) / h.width, double(height) / h.height);
    return std::make_unique<ImageBandWriter>(path, width, height, h.channels, h.format, h.alpha_channel, &metadata,
                                             encode);
  }

 private:
  ImageRowReader reader_;
};

}  // namespace

std::unique_ptr<InputImage> open_input_image(const std::string& path, const ImageReadLimits& limits) {
  if (auto png = PngReader::open(path, limits))
    return std::make_unique<PngInputImage>(
        std::move(png), [](const std::string& output, int width, int height, const ImageHeader& source,
                           const PngMetadata& metadata, const EncodeOptions& encode) -> std::unique_ptr<OutputImage> {
          const OIIO::ParamValueList attributes = as_attributes(metadata);
          return std::make_unique<ImageBandWriter>(output, width, height, source.channels, source.format,
                                                   source.alpha_channel, &attributes, encode);
        });
  return std::make_unique<OiioInputImage>(path, limits);
}

void check_output_image(const std::string& path, int width, int height, const ImageHeader& source,
                        const EncodeOptions& encode) {
  check_image_writable(path, width, height, source.channels, source.format, source.alpha_channel, encode);
}

std::string output_format_name(const std::string& path) {
  auto out = OIIO::ImageOutput::create(path);
  return out ? std::string(out->format_name()) : std::string();
}

}  // namespace ddt
