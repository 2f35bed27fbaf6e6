// The `ddtscale` front's image formats (io/image_formats.hpp): PNG read
// through libpng, written through libpng or, as EXR, through OpenEXR
// (io/exr_file.hpp), without OpenImageIO. Anything else throws
// NeedsOpenImageIO before a byte is written, and the front runs its
// command line again as ddtscale-full.

#include "io/image_formats.hpp"
#include "io/exr_file.hpp"
#include "io/png_images.hpp"
#include "util/file_names.hpp"

namespace ddt {

std::unique_ptr<InputImage> open_input_image(const std::string& path, const ImageReadLimits& limits) {
  auto png = PngReader::open(path, limits);
  if (!png) throw NeedsOpenImageIO("'" + path + "' is not a PNG read without OpenImageIO");
  return std::make_unique<PngInputImage>(
      std::move(png), [](const std::string& output, int, int, const ImageHeader&, const PngMetadata&,
                         const EncodeOptions&) -> std::unique_ptr<OutputImage> {
        throw NeedsOpenImageIO("'" + output + "' is not a PNG or EXR written without OpenImageIO");
      });
}

void check_output_image(const std::string& path, int width, int height, const ImageHeader& source,
                        const EncodeOptions& encode) {
  const bool alpha_last = source.alpha_channel < 0 || source.alpha_channel == source.channels - 1;
  // The EXR's metadata is checked when it is created (its text may go to
  // OpenImageIO), still before the work.
  const bool exr = exr_writes(path, width, height, source.channels, source.format, ExrMetadata{}, encode);
  if (!alpha_last || !(png_writes(path, width, height, source.channels, encode) || exr))
    throw NeedsOpenImageIO("'" + path + "' is not a PNG or EXR written without OpenImageIO");
}

std::string output_format_name(const std::string& path) {
  if (lower_extension(path) == ".png") return "png";
  if (lower_extension(path) == ".exr") return "openexr";
  throw NeedsOpenImageIO("'" + path + "' is not a PNG or EXR");
}

}  // namespace ddt
