// libFuzzer target: an image read as the CLI reads it (read_image: every
// OpenImageIO format plugin tried on a file with no extension, our header
// checks, then the decode), and the same bytes as a .png through libpng
// alone (PngReader, the `ddtscale` front's reader, by bands and again from
// the top). Any input must give an image, a refusal (null) or a ddt::Error.
#include "util/error.hpp"
#include "io/image_io.hpp"
#include "io/png_file.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "ddtscale-fuzz-image-XXXXXX").string();
    return std::filesystem::path(mkdtemp(pattern.data())) / "input";
  }();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                               static_cast<std::streamsize>(size));
  const std::filesystem::path png = path.string() + ".png";
  std::filesystem::copy_file(path, png, std::filesystem::copy_options::overwrite_existing);
  ddt::ImageReadLimits limits;
  limits.max_pixels = 1 << 22;  // as --max-input-pixels: keeps each run within the fuzzer's memory
  try {
    const ddt::ImageFile file = ddt::read_image(path.string(), limits);
    if (file.image.pixel_count() > std::size_t(1) << 22) __builtin_trap();
    for (float v : file.image.pixels)
      if (!std::isfinite(v)) __builtin_trap();  // read_image refuses NaN and infinities
  } catch (const ddt::Error&) {
  }
  try {
    if (auto reader = ddt::PngReader::open(png.string(), limits)) {
      const ddt::ImageHeader& h = reader->header();
      std::vector<float> rows(std::size_t(h.width) * h.channels * h.height);
      reader->read(0, h.height / 2, rows.data());
      reader->read(h.height / 2, h.height, rows.data() + std::size_t(h.width) * h.channels * (h.height / 2));
      reader->read(0, 1, rows.data());
      for (float v : rows)
        if (!(v >= 0.0f && v <= 1.0f)) __builtin_trap();
    }
  } catch (const ddt::Error&) {
  }
  return 0;
}
