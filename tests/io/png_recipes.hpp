#pragma once
// PNG files made for the tests of io/png_file.hpp and io/exr_file.hpp:
// libpng writing the chunks a test asks for, float samples on and beside
// the rounding boundaries, and an image handed to an output in bands.

#include "io/image_formats.hpp"
#include "util/image.hpp"

#include <doctest/doctest.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace ddt::test {

// A PNG as libpng writes it, with the chunks a test asks for.
struct PngRecipe {
  int width = 13, height = 9;
  int colour = PNG_COLOR_TYPE_RGB;
  int depth = 8;
  bool interlaced = false;
  bool transparency = false;  // tRNS
  bool profile = false;       // iCCP
  bool time = false;
  bool gamma = false;         // gAMA (1/2.2), no sRGB
  int resolution_unit = -1;   // pHYs: PNG_RESOLUTION_METER or _UNKNOWN; -1: none
  std::vector<std::pair<std::string, std::string>> text;
  unsigned seed = 1;
};

inline int channels_of(int colour) {
  return colour == PNG_COLOR_TYPE_GRAY ? 1 : colour == PNG_COLOR_TYPE_GRAY_ALPHA ? 2 : colour == PNG_COLOR_TYPE_RGB ? 3
         : colour == PNG_COLOR_TYPE_RGB_ALPHA                                   ? 4
                                                                               : 1;
}

inline bool write_recipe(std::FILE* file, const PngRecipe& r, std::vector<std::vector<unsigned char>>& rows,
                  std::vector<png_text>& text) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, r.width, r.height, r.depth, r.colour,
               r.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_color palette[16];
  for (int i = 0; i < 16; ++i) palette[i] = {png_byte(i * 16), png_byte(255 - i * 9), png_byte(i * 5 + 3)};
  if (r.colour == PNG_COLOR_TYPE_PALETTE) png_set_PLTE(png, info, palette, 1 << std::min(r.depth, 4));
  png_color_16 transparent{};
  png_byte alpha[1] = {0};
  if (r.transparency && r.colour == PNG_COLOR_TYPE_PALETTE) png_set_tRNS(png, info, alpha, 1, nullptr);
  else if (r.transparency) png_set_tRNS(png, info, nullptr, 0, &transparent);
  // The smallest profile libpng takes: a 128-byte header and no tags.
  std::vector<png_byte> icc(132, 0);
  auto put = [&](int at, const char* four) { std::copy(four, four + 4, icc.begin() + at); };
  icc[3] = 132;
  icc[8] = 2, icc[9] = 0x10;
  put(12, "mntr"), put(16, "RGB "), put(20, "XYZ "), put(36, "acsp");
  const png_byte d50[12] = {0, 0, 0xf6, 0xd6, 0, 1, 0, 0, 0, 0, 0xd3, 0x2d};
  std::copy(d50, d50 + 12, icc.begin() + 68);
  if (r.profile) png_set_iCCP(png, info, "test", 0, icc.data(), png_uint_32(icc.size()));
  png_time when{2017, 8, 12, 9, 43, 55};
  if (r.time) png_set_tIME(png, info, &when);
  if (r.gamma) png_set_gAMA(png, info, 1.0 / 2.2);
  if (r.resolution_unit >= 0) png_set_pHYs(png, info, 11811, 2835, r.resolution_unit);
  if (!text.empty()) png_set_text(png, info, text.data(), int(text.size()));
  png_set_option(png, PNG_SKIP_sRGB_CHECK_PROFILE, PNG_OPTION_ON);
  png_write_info(png, info);
  const int passes = png_set_interlace_handling(png);
  for (int pass = 0; pass < passes; ++pass)
    for (auto& row : rows) png_write_row(png, row.data());
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

inline void make_png(const std::string& path, const PngRecipe& r) {
  std::mt19937 rng(r.seed);
  const int bits = r.depth * channels_of(r.colour);
  const std::size_t row_bytes = (std::size_t(r.width) * bits + 7) / 8;
  std::vector<std::vector<unsigned char>> rows(r.height, std::vector<unsigned char>(row_bytes));
  for (auto& row : rows)
    for (auto& b : row) b = static_cast<unsigned char>(rng());
  if (r.colour == PNG_COLOR_TYPE_PALETTE && r.depth == 8)
    for (auto& row : rows)
      for (auto& b : row) b &= 15;  // within the palette
  std::vector<png_text> text;
  for (const auto& [key, value] : r.text) {
    png_text t{};
    t.compression = PNG_TEXT_COMPRESSION_NONE;
    t.key = const_cast<char*>(key.c_str());
    t.text = const_cast<char*>(value.c_str());
    text.push_back(t);
  }
  std::FILE* file = std::fopen(path.c_str(), "wb");
  REQUIRE(file);
  const bool ok = write_recipe(file, r, rows, text);
  std::fclose(file);
  REQUIRE(ok);
}

inline std::vector<char> bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Samples on and beside the rounding boundaries of 8 and 16 bits, and
// outside 0..1.
inline Image awkward_values(int width, int height, int channels, unsigned seed) {
  Image image(width, height, channels);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.05f, 1.05f);
  std::uniform_int_distribution<int> code(0, 255);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    float v = u(rng);
    if (i % 3 == 0) v = (code(rng) + 0.5f) / 255.0f;
    if (i % 7 == 0) v = std::nextafter(v, i % 2 ? 2.0f : -1.0f);
    if (i % 11 == 0) v = code(rng) * (1.0f / 255.0f);
    image.pixels[i] = v;
  }
  if (channels == 2 || channels == 4)  // alpha: some exactly 0 and 1, where nothing is divided
    for (std::size_t p = 0; p < image.pixel_count(); p += 5) {
      image.pixels[p * channels + channels - 1] = 0.0f;
      if (p + 1 < image.pixel_count()) image.pixels[(p + 1) * channels + channels - 1] = 1.0f;
    }
  return image;
}

// Hands `image` to `out` in two bands, as the file pipeline hands them,
// and finishes it.
inline void write_in_two_bands(OutputImage& out, const Image& image) {
  const int half = image.height / 2;
  Image top(image.width, half, image.channels), bottom(image.width, image.height - half, image.channels);
  std::copy(image.pixels.begin(), image.pixels.begin() + std::ptrdiff_t(top.pixels.size()), top.pixels.begin());
  std::copy(image.pixels.begin() + std::ptrdiff_t(top.pixels.size()), image.pixels.end(), bottom.pixels.begin());
  out.write(std::move(top), 0);
  out.write(std::move(bottom), half);
  out.finish();
}

}  // namespace ddt::test
