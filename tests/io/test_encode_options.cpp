#include "io/encode_options.hpp"
#include "io/image_io.hpp"
#include "util/error.hpp"

#include "test_support.hpp"

#include <OpenImageIO/imageio.h>
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

using namespace ddt;
using ddt::test::TempDir;

namespace {

// A smooth gradient with fine texture: compressible, but not trivially.
Image texture(int w, int h) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        img.at(x, y, c) = 0.5f + 0.3f * std::sin(0.05f * x + 0.07f * y + c) + 0.02f * std::sin(1.3f * x * y + c);
  return img;
}

OIIO::ImageSpec spec_of(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  REQUIRE(in);
  return in->spec();
}

}  // namespace

TEST_CASE("write_image: the DWA level of --compression dwaa:LEVEL reaches the file") {
  // OpenImageIO 2.4 takes the level from the compression's name only
  // ("dwaa:LEVEL"); given apart it was replaced by the default, 45.
  const TempDir dir;
  const Image img = texture(64, 48);
  std::map<int, std::uintmax_t> sizes;
  for (int level : {5, 45, 400}) {
    EncodeOptions encode;
    encode.compression = "dwaa:" + std::to_string(level);
    const std::string path = dir / ("dwa" + std::to_string(level) + ".exr");
    write_image(path, img, SampleFormat::uint8, -1, nullptr, encode);
    CHECK(spec_of(path).get_float_attribute("openexr:dwaCompressionLevel") == float(level));
    sizes[level] = std::filesystem::file_size(path);
  }
  CHECK(sizes[5] > sizes[45]);  // a lower level keeps more
  CHECK(sizes[45] > sizes[400]);
}

TEST_CASE("write_image: PNG levels and filters round-trip the same pixels - a higher level is no larger") {
  const TempDir dir;
  const Image img = texture(96, 64);
  const ImageFile reference = [&] {
    write_image(dir / "default.png", img, SampleFormat::uint8);
    return read_image(dir / "default.png");
  }();
  std::uintmax_t previous = 0;
  for (const char* level : {"0:none", "1:up", "9:adaptive"}) {
    EncodeOptions encode;
    encode.compression = level;
    const std::string path = dir / (std::string("l") + level[0] + ".png");
    write_image(path, img, SampleFormat::uint8, -1, nullptr, encode);
    CHECK(read_image(path).image.pixels == reference.image.pixels);
    const std::uintmax_t size = std::filesystem::file_size(path);
    if (previous) CHECK(size <= previous);
    previous = size;
  }
  // Level 0 stores the rows: at least the raw bytes (3 per pixel, 1 filter byte per row).
  CHECK(std::filesystem::file_size(dir / "l0.png") >= std::uintmax_t(96 * 64 * 3 + 64));
}

TEST_CASE("write_image: the PNG strategy reaches zlib - the default, fast, is zlib's 1:up:rle there") {
  const TempDir dir;
  const Image img = texture(96, 64);
  std::map<std::string, std::uintmax_t> sizes;
  std::vector<float> first;
  const char* const texts[] = {"", "1:up:rle", "1:up", "1:up:huffman", "1:up:default"};
  const char* const names[] = {"s0.png", "s1.png", "s2.png", "s3.png", "s4.png"};
  for (int i = 0; i < 5; ++i) {
    const std::string text = texts[i];
    EncodeOptions encode;
    encode.compression = text;
    const std::string path = dir / names[i];
    write_image(path, img, SampleFormat::uint8, -1, nullptr, encode);
    const ImageFile back = read_image(path);
    if (first.empty()) first = back.image.pixels;
    CHECK(back.image.pixels == first);
    sizes[text] = std::filesystem::file_size(path);
  }
  CHECK(default_compression("png") == "fast");  // igzip where ddtscale writes the PNG itself (png_idat.hpp)
  CHECK(sizes[""] == sizes["1:up:rle"]);
  CHECK(sizes["1:up"] == sizes["1:up:default"]);  // zlib's default strategy when none is named
  // Huffman coding alone finds no repeated strings: other bytes than the others.
  CHECK(sizes["1:up:huffman"] != sizes["1:up:default"]);
  CHECK(sizes["1:up:huffman"] != sizes["1:up:rle"]);
}

TEST_CASE("write_image: EXR compression, --half and --float reach the file") {
  const TempDir dir;
  const Image img = texture(40, 30);
  auto within_half = [&](const Image& back) {  // half floats: 11 significant bits
    bool all = true;
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
      all = all && std::abs(back.pixels[i] - img.pixels[i]) <= std::abs(img.pixels[i]) * (1.0f / 2048);
    return all;
  };
  // By default the source's precision decides: half from 8-bit and half
  // sources, 32-bit floats from 16-bit and float ones.
  for (SampleFormat source : {SampleFormat::uint8, SampleFormat::half, SampleFormat::uint16, SampleFormat::float32}) {
    const bool half = source == SampleFormat::uint8 || source == SampleFormat::half;
    CAPTURE(half);
    write_image(dir / "default.exr", img, source);
    const OIIO::ImageSpec spec = spec_of(dir / "default.exr");
    CHECK(spec.get_string_attribute("compression") == default_compression("openexr"));
    CHECK(spec.format == (half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT));
    const Image back = read_image(dir / "default.exr").image;
    CHECK(within_half(back));
    if (!half) CHECK(back.pixels == img.pixels);
  }

  EncodeOptions encode;
  encode.compression = "zip";
  encode.half = true;
  write_image(dir / "half.exr", img, SampleFormat::float32, -1, nullptr, encode);
  OIIO::ImageSpec spec = spec_of(dir / "half.exr");
  CHECK(spec.format == OIIO::TypeDesc::HALF);
  CHECK(spec.get_string_attribute("compression") == "zip");
  const ImageFile half = read_image(dir / "half.exr");
  CHECK(half.format == SampleFormat::half);
  CHECK(within_half(half.image));

  encode.half = false;
  encode.full_float = true;
  write_image(dir / "float.exr", img, SampleFormat::uint8, -1, nullptr, encode);
  CHECK(spec_of(dir / "float.exr").format == OIIO::TypeDesc::FLOAT);
  CHECK(read_image(dir / "float.exr").image.pixels == img.pixels);
  encode.half = true;
  CHECK_THROWS_WITH_AS(check_encode_options("x.exr", encode), "--half and --float: give one of them", Error);
  encode.half = false;
  CHECK_THROWS_WITH_AS(check_encode_options("x.png", encode), "--float is for EXR output", Error);
}

TEST_CASE("write_image: TIFF compression and JPEG quality reach the file") {
  const TempDir dir;
  const Image img = texture(64, 48);
  EncodeOptions encode;
  encode.compression = "lzw";
  write_image(dir / "a.tif", img, SampleFormat::uint8, -1, nullptr, encode);
  CHECK(spec_of(dir / "a.tif").get_string_attribute("compression") == "lzw");
  CHECK(read_image(dir / "a.tif").image.pixels == read_image(dir / "a.tif").image.pixels);
  // The default is zip at zlib level 1; `zip` alone is level 6, smaller.
  CHECK(default_compression("tiff") == "zip:1");
  write_image(dir / "default.tif", img, SampleFormat::uint8);
  EncodeOptions one, six;
  one.compression = "zip:1";
  six.compression = "zip";
  write_image(dir / "one.tif", img, SampleFormat::uint8, -1, nullptr, one);
  write_image(dir / "six.tif", img, SampleFormat::uint8, -1, nullptr, six);
  CHECK(spec_of(dir / "default.tif").get_string_attribute("compression") == "zip");
  CHECK(std::filesystem::file_size(dir / "default.tif") == std::filesystem::file_size(dir / "one.tif"));
  CHECK(std::filesystem::file_size(dir / "six.tif") < std::filesystem::file_size(dir / "one.tif"));
  CHECK(read_image(dir / "default.tif").image.pixels == read_image(dir / "six.tif").image.pixels);
  EncodeOptions low, high;
  low.quality = 20;
  high.quality = 98;
  write_image(dir / "low.jpg", img, SampleFormat::uint8, -1, nullptr, low);
  write_image(dir / "high.jpg", img, SampleFormat::uint8, -1, nullptr, high);
  CHECK(std::filesystem::file_size(dir / "low.jpg") < std::filesystem::file_size(dir / "high.jpg"));
}

TEST_CASE("check_encode_options: bad values are refused with the option's name") {
  auto refused = [](const std::string& path, EncodeOptions e, const std::string& words) {
    try {
      check_encode_options(path, e);
      FAIL("accepted: " << path << " " << e.compression);
    } catch (const Error& err) {
      const std::string what = err.what();
      CHECK_MESSAGE(what.find(words) != std::string::npos, what);
      CHECK(what.find('\n') == std::string::npos);
    }
  };
  struct Refused {
    const char *path, *compression, *words;
  };
  for (const Refused& r : {Refused{"o.png", "10", "from 0 to 9"}, Refused{"o.png", "3:diagonal", "unknown PNG filter"},
                           Refused{"o.png", "1:up:zigzag", "unknown zlib strategy"},
                           Refused{"o.png", "fast:adaptive", "fast takes a filter only"},
                           Refused{"o.png", "fast:up:rle", "fast takes a filter only"},
                           Refused{"o.png", "fast:diagonal", "unknown PNG filter"},
                           Refused{"o.exr", "zap", "EXR compression is one of"},
                           Refused{"o.exr", "zip:4", "only dwaa and dwab"}, Refused{"o.tif", "zip:12", "from 1 to 9"},
                           Refused{"o.jpg", "zip", "--compression"}}) {
    EncodeOptions e;
    e.compression = r.compression;
    refused(r.path, e, r.words);
  }
  EncodeOptions q;
  q.quality = 50;
  refused("o.png", q, "--quality");
  EncodeOptions h;
  h.half = true;
  refused("o.png", h, "--half");
  EncodeOptions fine;
  fine.compression = "dwaa:60";
  CHECK_NOTHROW(check_encode_options("o.exr", fine));
  fine.compression = "6:paeth";
  CHECK_NOTHROW(check_encode_options("o.png", fine));
  fine.compression = "fast:paeth";
  CHECK_NOTHROW(check_encode_options("o.png", fine));
}
