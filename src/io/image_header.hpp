#pragma once
// What an image file's header says, and the limits on what is decoded:
// shared by the readers (image_io.hpp through OpenImageIO, png_file.hpp
// through libpng) and the file pipeline (pipeline/file_upscale.hpp),
// without OpenImageIO's headers.

#include "util/size_limits.hpp"

#include <functional>
#include <string>

namespace ddt {

// How samples were stored in the file; used to pick the output depth.
enum class SampleFormat { uint8, uint16, half, float32 };

// What an image file's header says, before any pixel is decoded.
struct ImageHeader {
  int width = 0, height = 0, channels = 0;
  SampleFormat format = SampleFormat::uint8;
  int alpha_channel = -1;
};

// Limits on what read_image decodes (size_limits.hpp). The header's size is
// checked before any pixel is decoded: width x height (and a tile's) against
// max_pixels, the decoded floats against the memory available; then
// `check`, when set, sees the header and may throw (the CLI sizes its whole
// job there: output size, output format, memory).
struct ImageReadLimits {
  long long max_pixels = default_max_input_pixels();
  std::string option = "--max-input-pixels";  // named in the refusal
  std::function<void(const ImageHeader&)> check;
};

}  // namespace ddt
