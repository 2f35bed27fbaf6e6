// The input's statistics (input_statistics.hpp): each channel's range and
// the code grid, the same wherever in the image (which block of pixels the
// threads split it into) the deciding sample lies.
#include "consistency/input_statistics.hpp"
#include "io/png_file.hpp"
#include "io/png_recipes.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <random>
#include <vector>

using ddt::Image;
using ddt::InputStatistics;

namespace {

// A 300x300 RGB image (two blocks of 65,536 pixels and a part) of 8-bit
// codes, channel c in [0.1 c, 0.1 c + 0.5].
Image coded_image() {
  Image image(300, 300, 3);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> code(0, 127);
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    image.pixels[i] = static_cast<float>((26 * (i % 3) + code(rng)) / 255.0);
  return image;
}

// The statistics as the rows of a source read in chunks.
InputStatistics by_rows(const Image& image) {
  const ddt::RowSource source{image.width, image.height, image.channels, [&](int first, int end, float* rows) {
                                const std::size_t row = static_cast<std::size_t>(image.width) * image.channels;
                                std::copy(image.pixels.begin() + static_cast<std::ptrdiff_t>(row * first),
                                          image.pixels.begin() + static_cast<std::ptrdiff_t>(row * end), rows);
                              }};
  return ddt::input_statistics(source);
}

}  // namespace

TEST_CASE("input_statistics: each channel's range, its extremes in any block") {
  const std::size_t last = 300 * 300 - 1;
  for (std::size_t pixel : {std::size_t(0), std::size_t(65535), std::size_t(65536), last}) {
    CAPTURE(pixel);
    Image image = coded_image();
    image.pixels[3 * pixel + 1] = 250 / 255.0f;  // the greatest of channel 1
    image.pixels[3 * pixel + 2] = 1 / 255.0f;    // the least of channel 2
    const InputStatistics s = ddt::input_statistics(image);
    REQUIRE(s.min.size() == 3);
    CHECK(s.max[1] == 250 / 255.0f);
    CHECK(s.min[2] == 1 / 255.0f);
    CHECK(s.min[0] >= 0.0f);
    CHECK(s.max[0] <= 127 / 255.0f);
    const InputStatistics rows = by_rows(image);
    CHECK(rows.min == s.min);
    CHECK(rows.max == s.max);
    CHECK(rows.quantum == s.quantum);
  }
}

TEST_CASE("input_statistics: the code grid, decided by one sample in any block") {
  CHECK(ddt::input_statistics(coded_image()).quantum == doctest::Approx(1 / 255.0));
  for (std::size_t sample : {std::size_t(0), std::size_t(3 * 65536 + 2), std::size_t(3 * 300 * 300 - 1)}) {
    CAPTURE(sample);
    Image sixteen = coded_image();
    sixteen.pixels[sample] = static_cast<float>(1000 / 65535.0);  // on the 16-bit grid only
    CHECK(ddt::input_statistics(sixteen).quantum == doctest::Approx(1 / 65535.0));
    CHECK(by_rows(sixteen).quantum == doctest::Approx(1 / 65535.0));
    Image off = coded_image();
    off.pixels[sample] = 0.123456f;  // on neither
    CHECK(ddt::input_statistics(off).quantum == 0);
    CHECK(by_rows(off).quantum == 0);
  }
}

TEST_CASE("input_statistics: 16-bit codes read as floats are on the 16-bit grid") {
  // Every code, as the float nearest it and as the PNG reader makes it
  // (code times the float 1/65535): a quarter of them are off a code by
  // more than a thousandth in float.
  Image all(256, 256, 1);
  for (std::size_t k = 0; k < all.pixels.size(); ++k) all.pixels[k] = static_cast<float>(k / 65535.0);
  CHECK(ddt::input_statistics(all).quantum == doctest::Approx(1 / 65535.0));
  for (std::size_t k = 0; k < all.pixels.size(); ++k) all.pixels[k] = float(k) * (1.0f / 65535.0f);
  CHECK(ddt::input_statistics(all).quantum == doctest::Approx(1 / 65535.0));

  const std::string path = (std::filesystem::temp_directory_path() / "ddtscale_statistics_16bit.png").string();
  ddt::test::PngRecipe recipe;
  recipe.width = 97, recipe.height = 61, recipe.depth = 16;
  ddt::test::make_png(path, recipe);
  auto reader = ddt::PngReader::open(path);
  REQUIRE(reader);
  Image image(97, 61, 3);
  reader->read(0, 61, image.pixels.data());
  std::filesystem::remove(path);
  CHECK(ddt::input_statistics(image).quantum == doctest::Approx(1 / 65535.0));
}
