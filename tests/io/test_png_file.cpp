// PNG through libpng alone (io/png_file.hpp) against OpenImageIO's PNG
// plugin: the same floats read, the same bytes written, the same metadata
// carried; and what is left to OpenImageIO.

#include "io/image_io.hpp"
#include "io/png_file.hpp"
#include "io/png_images.hpp"
#include "util/error.hpp"

#include "png_recipes.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>
#include <png.h>
#include <zlib.h>

#include <array>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

using namespace ddt;
using ddt::test::TempDir;
using namespace ddt::test;

namespace {

// Writes `image` through libpng alone, as the file pipeline does.
void write_natively(const std::string& path, const Image& image, SampleFormat format, const PngMetadata* metadata,
                    const EncodeOptions& encode) {
  auto out = create_png_output(path, image.width, image.height, image.channels, format, metadata, encode);
  write_in_two_bands(*out, image);
}

// A PNG file's chunks other than IDAT (type and data, in order, every CRC
// checked) and its image data inflated: what two encoders of the same
// image with the same filter must agree on, whatever their compressor.
struct PngLayout {
  std::vector<std::pair<std::string, std::vector<unsigned char>>> chunks;
  std::vector<unsigned char> image_data;
  bool valid = true;
  int idat_chunks = 0;
};

PngLayout png_layout(const std::string& path) {
  const std::vector<char> file = bytes_of(path);
  const auto* b = reinterpret_cast<const unsigned char*>(file.data());
  PngLayout layout;
  static constexpr std::array<unsigned char, 8> signature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (file.size() < 8 || !std::equal(signature.begin(), signature.end(), b)) return layout.valid = false, layout;
  auto be32 = [&](std::size_t i) {
    return std::uint32_t(b[i]) << 24 | std::uint32_t(b[i + 1]) << 16 | std::uint32_t(b[i + 2]) << 8 | b[i + 3];
  };
  std::vector<unsigned char> compressed;
  std::size_t at = 8;
  bool ended = false;
  while (at + 12 <= file.size() && !ended) {
    const std::uint32_t n = be32(at);
    if (at + 12 + n > file.size()) break;
    const std::string type(file.data() + at + 4, 4);
    layout.valid = layout.valid && crc32(0, b + at + 4, uInt(n + 4)) == be32(at + 8 + n);
    if (type == "IDAT") {
      compressed.insert(compressed.end(), b + at + 8, b + at + 8 + n);
      ++layout.idat_chunks;
    } else {
      layout.chunks.emplace_back(type, std::vector<unsigned char>(b + at + 8, b + at + 8 + n));
    }
    ended = type == "IEND";
    at += 12 + n;
  }
  layout.valid = layout.valid && ended && at == file.size();
  z_stream z{};
  std::vector<unsigned char> out(1 << 16);
  if (inflateInit(&z) != Z_OK) return layout.valid = false, layout;
  z.next_in = compressed.data();
  z.avail_in = uInt(compressed.size());
  int status = Z_OK;
  while (status == Z_OK) {
    z.next_out = out.data();
    z.avail_out = uInt(out.size());
    status = inflate(&z, Z_NO_FLUSH);
    layout.image_data.insert(layout.image_data.end(), out.data(), out.data() + (out.size() - z.avail_out));
  }
  layout.valid = layout.valid && status == Z_STREAM_END && z.avail_in == 0;
  inflateEnd(&z);
  return layout;
}

}  // namespace

TEST_CASE("PngReader: the floats, size and sample type OpenImageIO reads, by bands and again from the top") {
  const TempDir dir;
  struct Kind {
    int colour, depth;
  };
  for (const Kind k : {Kind{PNG_COLOR_TYPE_RGB, 8}, Kind{PNG_COLOR_TYPE_RGB, 16}, Kind{PNG_COLOR_TYPE_GRAY, 8},
                       Kind{PNG_COLOR_TYPE_GRAY, 16}, Kind{PNG_COLOR_TYPE_GRAY, 1}, Kind{PNG_COLOR_TYPE_GRAY, 2},
                       Kind{PNG_COLOR_TYPE_GRAY, 4}, Kind{PNG_COLOR_TYPE_PALETTE, 8},
                       Kind{PNG_COLOR_TYPE_PALETTE, 4}, Kind{PNG_COLOR_TYPE_RGB_ALPHA, 8},
                       Kind{PNG_COLOR_TYPE_RGB_ALPHA, 16}, Kind{PNG_COLOR_TYPE_GRAY_ALPHA, 8},
                       Kind{PNG_COLOR_TYPE_GRAY_ALPHA, 16}}) {
    CAPTURE(k.colour);
    CAPTURE(k.depth);
    PngRecipe r;
    r.colour = k.colour, r.depth = k.depth, r.seed = unsigned(k.colour * 100 + k.depth);
    const std::string path = dir / "in.png";
    make_png(path, r);
    const ImageFile expected = read_image(path);
    auto reader = PngReader::open(path);
    REQUIRE(reader);
    const ImageHeader& h = reader->header();
    CHECK(h.width == expected.image.width);
    CHECK(h.height == expected.image.height);
    CHECK(h.channels == expected.image.channels);
    CHECK(h.format == expected.format);
    CHECK(h.alpha_channel == expected.alpha_channel);
    std::vector<float> rows(expected.image.pixels.size());
    const std::size_t row = std::size_t(h.width) * h.channels;
    reader->read(0, 4, rows.data());
    reader->read(4, h.height, rows.data() + 4 * row);
    CHECK(rows == expected.image.pixels);
    std::vector<float> again(2 * row);
    reader->read(2, 4, again.data());  // above the last row read: decoded again from the top
    CHECK(std::equal(again.begin(), again.end(), expected.image.pixels.begin() + std::ptrdiff_t(2 * row)));
  }
}

TEST_CASE("PngReader: an interlaced image, decoded whole, reads as OpenImageIO reads it") {
  const TempDir dir;
  for (const int colour : {PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA, PNG_COLOR_TYPE_GRAY}) {
    CAPTURE(colour);
    PngRecipe r;
    r.colour = colour, r.interlaced = true, r.width = 23, r.height = 17, r.seed = unsigned(colour + 11);
    make_png(dir / "in.png", r);
    const ImageFile expected = read_image(dir / "in.png");
    auto reader = PngReader::open(dir / "in.png");
    REQUIRE(reader);
    const std::size_t row = std::size_t(reader->header().width) * reader->header().channels;
    std::vector<float> rows(expected.image.pixels.size());
    reader->read(5, r.height, rows.data() + 5 * row);
    reader->read(0, 5, rows.data());
    CHECK(rows == expected.image.pixels);
  }
}

TEST_CASE("PngReader: transparency (tRNS) becomes alpha, associated, as OpenImageIO reads it") {
  const TempDir dir;
  for (const int colour : {PNG_COLOR_TYPE_PALETTE, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_RGB}) {
    CAPTURE(colour);
    PngRecipe r;
    r.colour = colour, r.transparency = true, r.seed = unsigned(colour + 7);
    make_png(dir / "in.png", r);
    const ImageFile expected = read_image(dir / "in.png");
    auto reader = PngReader::open(dir / "in.png");
    REQUIRE(reader);
    CHECK(reader->header().channels == expected.image.channels);
    CHECK(reader->header().alpha_channel == expected.alpha_channel);
    std::vector<float> rows(expected.image.pixels.size());
    reader->read(0, reader->header().height, rows.data());
    CHECK(rows == expected.image.pixels);
  }
}

TEST_CASE("PngReader: alpha under a gamma, special text and damaged files are left to OpenImageIO") {
  const TempDir dir;
  const std::string path = dir / "in.png";
  auto declined = [&](PngRecipe r) {
    make_png(path, r);
    return PngReader::open(path) == nullptr;
  };
  PngRecipe plain;
  CHECK_FALSE(declined(plain));
  PngRecipe gamma = plain;  // taken: OpenImageIO reads a gamma as an attribute an enlargement drops
  gamma.gamma = true;
  CHECK_FALSE(declined(gamma));
  PngRecipe gamma_alpha = gamma;  // OpenImageIO associates alpha in floats under a gamma
  gamma_alpha.colour = PNG_COLOR_TYPE_RGB_ALPHA;
  CHECK(declined(gamma_alpha));
  PngRecipe profiled = plain;  // taken: the profile is carried
  profiled.profile = true;
  CHECK_FALSE(declined(profiled));
  PngRecipe exif_text = plain;
  exif_text.text = {{"Raw profile type exif", "exif\n 4\n00000000"}};
  CHECK(declined(exif_text));
  PngRecipe twice = plain;
  twice.text = {{"Author", "a"}, {"Author", "b"}};
  CHECK(declined(twice));
  PngRecipe date_text = plain;
  date_text.text = {{"DateTime", "2020:01:01 00:00:00"}};
  CHECK(declined(date_text));

  // Not a PNG, or a damaged one: OpenImageIO says why.
  make_png(path, plain);
  std::vector<char> bytes = bytes_of(path);
  {
    std::ofstream cut(dir / "cut.png", std::ios::binary);
    cut.write(bytes.data(), std::streamsize(bytes.size() - 20));
  }
  CHECK(PngReader::open(dir / "cut.png") == nullptr);
  std::filesystem::copy_file(path, dir / "in.tif");
  CHECK(PngReader::open(dir / "in.tif") == nullptr);
  CHECK(PngReader::open(dir / "missing.png") == nullptr);
  {
    std::ofstream text_file(dir / "text.png");
    text_file << "not a PNG";
  }
  CHECK(PngReader::open(dir / "text.png") == nullptr);
}

TEST_CASE("PngReader: the header is checked as read_image checks it") {
  const TempDir dir;
  PngRecipe r;
  r.width = 40, r.height = 30;
  make_png(dir / "in.png", r);
  ImageReadLimits limits;
  limits.max_pixels = 1000;
  CHECK_THROWS_WITH_AS(PngReader::open(dir / "in.png", limits),
                       doctest::Contains("40x30 exceeds --max-input-pixels 1000"), Error);
  CHECK_THROWS_AS(read_image(dir / "in.png", limits), Error);
  int seen = 0;
  limits.max_pixels = 1 << 20;
  limits.check = [&](const ImageHeader& h) {
    seen = h.width * h.height;
    throw Error("refused by the job");
  };
  CHECK_THROWS_WITH_AS(PngReader::open(dir / "in.png", limits), "refused by the job", Error);
  CHECK(seen == 1200);
}

TEST_CASE("PngWriter: OpenImageIO's bytes, with the time, resolution and text carried and scaled") {
  const TempDir dir;
  struct Case {
    int width, height, colour, depth;
    int resolution_unit;
    bool time;
    std::vector<std::pair<std::string, std::string>> text;
    std::string compression;
    bool profile = false;
  };
  const std::vector<Case> cases = {
      {1, 1, PNG_COLOR_TYPE_RGB, 8, -1, false, {}, ""},
      {17, 5, PNG_COLOR_TYPE_RGB, 8, PNG_RESOLUTION_METER, true, {}, ""},
      {33, 7, PNG_COLOR_TYPE_GRAY, 8, PNG_RESOLUTION_UNKNOWN, false, {}, "9:paeth"},
      {20, 6, PNG_COLOR_TYPE_RGB, 16, -1, true, {}, "0:none"},
      {9, 9, PNG_COLOR_TYPE_GRAY, 16, -1, false, {}, "6:adaptive:filtered"},
      {12, 8, PNG_COLOR_TYPE_PALETTE, 8, -1, false, {}, "1:sub:huffman"},
      {19, 6, PNG_COLOR_TYPE_RGB_ALPHA, 8, -1, true, {}, ""},
      {7, 5, PNG_COLOR_TYPE_RGB_ALPHA, 16, -1, false, {}, ""},
      {10, 4, PNG_COLOR_TYPE_GRAY_ALPHA, 8, PNG_RESOLUTION_METER, false, {}, "9:paeth"},
      {11, 3, PNG_COLOR_TYPE_RGB, 8, PNG_RESOLUTION_METER, true, {{"Copyright", "c"}}, "", true},
      {6, 6, PNG_COLOR_TYPE_RGB_ALPHA, 16, -1, false, {}, "", true},
      {15, 4, PNG_COLOR_TYPE_RGB, 8, PNG_RESOLUTION_METER, true,
       {{"Author", "A. Painter"}, {"Software", "dropped"}, {"Copyright", "(c) 2026"}, {"title", "Scan 3"},
        {"Description", "a test"}, {"Exif:ImageHistory", "made here"}, {"Comment", "dropped too"}},
       "3:avg:fixed"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.width);
    CAPTURE(c.compression);
    PngRecipe r;
    r.width = c.width, r.height = c.height, r.colour = c.colour, r.depth = c.depth;
    r.resolution_unit = c.resolution_unit, r.time = c.time, r.text = c.text, r.profile = c.profile;
    make_png(dir / "in.png", r);
    auto reader = PngReader::open(dir / "in.png");
    REQUIRE(reader);
    const ImageFile file = read_image(dir / "in.png");
    const int out_w = c.width * 3, out_h = c.height * 2;
    const Image image = awkward_values(out_w, out_h, reader->header().channels, unsigned(c.width));
    // zlib: the same bytes (the default, fast, is zlib's 1:up:rle in OpenImageIO).
    EncodeOptions encode;
    encode.compression = c.compression.empty() ? "1:up:rle" : c.compression;
    const PngMetadata metadata = scaled_png_metadata(reader->metadata(), 3.0, 2.0);
    write_natively(dir / "native.png", image, reader->header().format, &metadata, encode);
    const auto attributes = scaled_metadata(file.metadata, 3.0, 2.0);
    write_image(dir / "oiio.png", image, file.format, file.alpha_channel, &attributes, encode);
    CHECK(bytes_of(dir / "native.png") == bytes_of(dir / "oiio.png"));
    // igzip (the default): the same chunks, and the same filtered rows inside.
    if (c.compression.empty()) {
      write_natively(dir / "fast.png", image, reader->header().format, &metadata, {});
      write_image(dir / "oiio_default.png", image, file.format, file.alpha_channel, &attributes, {});
      const PngLayout fast = png_layout(dir / "fast.png"), oiio = png_layout(dir / "oiio_default.png");
      CHECK(fast.valid);
      CHECK(oiio.valid);
      CHECK(fast.chunks == oiio.chunks);
      CHECK(fast.image_data == oiio.image_data);
      CHECK(bytes_of(dir / "fast.png") != bytes_of(dir / "oiio_default.png"));  // another compressor indeed
    }
  }
}

TEST_CASE("PngWriter: fast with every filter, 8 and 16 bits, many IDAT chunks: the rows zlib's libpng filters") {
  const TempDir dir;
  struct Kind {
    int width, height, channels;
    SampleFormat format;
  };
  // 700x400 RGB of noise holds more than one 256 KB chunk of image data.
  for (const Kind k : {Kind{1, 1, 1, SampleFormat::uint8}, Kind{9, 1, 3, SampleFormat::uint8}, Kind{1, 6, 1, SampleFormat::uint16},
                       Kind{13, 9, 2, SampleFormat::uint16},
                       Kind{31, 17, 4, SampleFormat::uint8}, Kind{700, 400, 3, SampleFormat::uint8}}) {
    for (const char* filter : {"none", "sub", "up", "avg", "paeth"}) {
      CAPTURE(k.width);
      CAPTURE(filter);
      const Image image = awkward_values(k.width, k.height, k.channels, unsigned(k.width + 5));
      EncodeOptions fast, zlib;
      fast.compression = std::string("fast:") + filter;
      zlib.compression = std::string("6:") + filter;
      write_natively(dir / "fast.png", image, k.format, nullptr, fast);
      write_natively(dir / "zlib.png", image, k.format, nullptr, zlib);
      const PngLayout a = png_layout(dir / "fast.png"), b = png_layout(dir / "zlib.png");
      CHECK(a.valid);
      CHECK(a.chunks == b.chunks);
      CHECK(a.image_data == b.image_data);
      if (k.width == 700) CHECK(a.idat_chunks > 1);
      const ImageFile back = read_image(dir / "fast.png");
      CHECK(back.image.pixels == read_image(dir / "zlib.png").image.pixels);
    }
  }
}

TEST_CASE("png_writes: 1 to 4 channel PNGs OpenImageIO would write, the rest left to it") {
  EncodeOptions plain;
  CHECK(png_writes("a.png", 10, 10, 3, plain));
  CHECK(png_writes("A.PNG", 10, 10, 1, plain));
  CHECK(png_writes("a.png", 10, 10, 4, plain));
  CHECK(png_writes("a.png", 10, 10, 2, plain));
  CHECK_FALSE(png_writes("a.png", 10, 10, 5, plain));
  CHECK_FALSE(png_writes("a.exr", 10, 10, 3, plain));
  CHECK_FALSE(png_writes("a.png", 70000, 10, 3, plain));
  EncodeOptions bad;
  bad.compression = "11";
  CHECK_FALSE(png_writes("a.png", 10, 10, 3, bad));
  EncodeOptions half;
  half.half = true;
  CHECK_FALSE(png_writes("a.png", 10, 10, 3, half));
}

TEST_CASE("PngWriter: a profile libpng refuses is dropped, as write_image drops it") {
  const TempDir dir;
  const Image image = awkward_values(9, 7, 3, 3);
  PngMetadata metadata;
  metadata.icc_profile.assign(60, 7);  // no ICC header
  EncodeOptions zlib;
  zlib.compression = "1:up:rle";
  write_natively(dir / "native.png", image, SampleFormat::uint8, &metadata, zlib);
  OIIO::ParamValueList attributes;
  attributes.attribute("ICCProfile", OIIO::TypeDesc(OIIO::TypeDesc::UINT8, 60), metadata.icc_profile.data());
  write_image(dir / "oiio.png", image, SampleFormat::uint8, -1, &attributes, zlib);
  CHECK(bytes_of(dir / "native.png") == bytes_of(dir / "oiio.png"));
  CHECK_FALSE(read_image(dir / "native.png").metadata.contains("ICCProfile"));
}
