// libFuzzer target: an image read as the CLI reads it (read_image: every
// OpenImageIO format plugin tried on a file with no extension, our header
// checks, then the decode). Any input must give an image or a ddt::Error.
#include "util/error.hpp"
#include "io/image_io.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "ddtscale-fuzz-image-XXXXXX").string();
    return std::filesystem::path(mkdtemp(pattern.data())) / "input";
  }();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                               static_cast<std::streamsize>(size));
  ddt::ImageReadLimits limits;
  limits.max_pixels = 1 << 22;  // as --max-input-pixels: keeps each run within the fuzzer's memory
  try {
    const ddt::ImageFile file = ddt::read_image(path.string(), limits);
    if (file.image.pixel_count() > std::size_t(1) << 22) __builtin_trap();
    for (float v : file.image.pixels)
      if (!std::isfinite(v)) __builtin_trap();  // read_image refuses NaN and infinities
  } catch (const ddt::Error&) {
  }
  return 0;
}
