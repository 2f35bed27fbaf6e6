#include "io/band_writer.hpp"
#include "io/image_io.hpp"
#include "util/error.hpp"

#include "test_support.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace ddt;
using ddt::test::TempDir;

namespace {

Image texture(int w, int h, int c) {
  Image img(w, h, c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) img.at(x, y, k) = 0.5f + 0.45f * std::sin(0.11f * x + 0.05f * y * (k + 1));
  return img;
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write_in_bands(const std::string& path, const Image& img, int band, SampleFormat format,
                    const OIIO::ParamValueList& metadata, const EncodeOptions& encode) {
  ImageBandWriter writer(path, img.width, img.height, img.channels, format, -1, &metadata, encode);
  for (int y = 0; y < img.height; y += band) {
    Image rows(img.width, std::min(band, img.height - y), img.channels);
    std::copy_n(img.pixels.begin() + static_cast<std::ptrdiff_t>(img.index(0, y)), rows.pixels.size(),
                rows.pixels.begin());
    writer.write(std::move(rows), y);
  }
  writer.finish();
}

}  // namespace

TEST_CASE("ImageBandWriter: the file written by bands is write_image's, byte for byte (PNG, TIFF, EXR, tiled)") {
  const TempDir dir;
  const Image img = texture(70, 53, 3);
  OIIO::ParamValueList metadata;
  metadata.attribute("DateTime", "2026:01:02 03:04:05");  // else each file carries the time it was written
  struct Case {
    const char* name;
    SampleFormat format;
    int tile;
    bool half;
  };
  for (const Case& c : {Case{"a.png", SampleFormat::uint8, 0, false}, Case{"b.png", SampleFormat::uint16, 0, false},
                        Case{"c.tif", SampleFormat::uint8, 0, false}, Case{"d.tif", SampleFormat::uint8, 32, false},
                        Case{"e.exr", SampleFormat::uint8, 0, false}, Case{"f.exr", SampleFormat::uint8, 16, true}}) {
    CAPTURE(std::string(c.name));
    EncodeOptions encode;
    encode.tile = c.tile;
    encode.half = c.half;
    const std::string whole = dir / (std::string("whole_") + c.name), bands = dir / c.name;
    write_image(whole, img, c.format, -1, &metadata, encode);
    for (int band : {1, 7, 53}) {
      write_in_bands(bands, img, band, c.format, metadata, encode);
      CAPTURE(band);
      if (c.tile > 0 && c.name[2] == 't') {
        // OpenImageIO's TIFF writer compresses tiles in parallel and stores
        // them in the order they finish (oiiotool's files differ from run to
        // run too), so only the pixels and the layout are compared.
        CHECK(read_image(bands).image.pixels == read_image(whole).image.pixels);
        auto in = OIIO::ImageInput::open(bands);
        REQUIRE(in);
        CHECK(in->spec().tile_width == c.tile);
      } else {
        CHECK(bytes_of(bands) == bytes_of(whole));
      }
    }
  }
}

TEST_CASE("ImageBandWriter: bands out of order or missing are refused - an unfinished writer leaves no file") {
  const TempDir dir;
  const Image img = texture(20, 10, 3);
  {
    ImageBandWriter writer(dir / "a.png", 20, 10, 3, SampleFormat::uint8);
    CHECK(writer.streaming());
    Image rows(20, 4, 3);
    CHECK_THROWS_AS(writer.write(rows, 2), Error);  // not row 0
    writer.write(rows, 0);
    CHECK_THROWS_AS(writer.write(Image(19, 2, 3), 4), Error);  // wrong width
    CHECK_THROWS_AS(writer.finish(), Error);                   // 6 rows missing
  }
  CHECK_FALSE(std::filesystem::exists(dir / "a.png"));
  for (const auto& entry : std::filesystem::directory_iterator(dir.path)) FAIL("left behind: " << entry.path());
}
