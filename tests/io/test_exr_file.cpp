// EXR through OpenEXR alone (io/exr_file.hpp) against OpenImageIO's EXR
// writer: a PNG enlarged into an EXR gives the same bytes, its metadata
// carried the same way; and what is left to OpenImageIO.

#include "io/exr_file.hpp"
#include "io/image_io.hpp"
#include "io/png_file.hpp"
#include "io/png_images.hpp"
#include "util/error.hpp"

#include "png_recipes.hpp"
#include "test_support.hpp"

#include <OpenImageIO/imageio.h>
#include <doctest/doctest.h>

#include <cmath>
#include <ctime>
#include <limits>
#include <string>
#include <vector>

using namespace ddt;
using namespace ddt::test;

namespace {

// Samples that round to every kind of half: on and beside the halfway
// points, subnormal, beyond the largest half, infinite, not a number.
void add_half_boundaries(Image& image) {
  const float special[] = {1.0f + 1.0f / 2048,  // halfway between two halves: to even
                           1.0f + 3.0f / 2048,
                           std::nextafter(1.0f + 1.0f / 2048, 2.0f),
                           6.0e-8f,
                           3.0e-5f,
                           65504.0f,
                           65520.0f,
                           1.0e6f,
                           -2.5f,
                           std::numeric_limits<float>::infinity(),
                           std::numeric_limits<float>::quiet_NaN()};
  for (std::size_t i = 0; i < image.pixels.size(); i += 13) image.pixels[i] = special[(i / 13) % std::size(special)];
}

// A PNG's enlargement written through the file pipeline's output image
// (PngInputImage::create_output).
void write_through_pipeline(const std::string& png, const std::string& path, const Image& image,
                            const EncodeOptions& encode) {
  auto reader = PngReader::open(png);
  REQUIRE(reader);
  PngInputImage input(std::move(reader), [](const std::string&, int, int, const ImageHeader&, const PngMetadata&,
                                            const EncodeOptions&) -> std::unique_ptr<OutputImage> {
    throw Error("left to OpenImageIO");
  });
  auto out = input.create_output(path, image.width, image.height, encode);
  write_in_two_bands(*out, image);
}

}  // namespace

TEST_CASE("ExrWriter: OpenImageIO's bytes for a PNG enlarged into an EXR, its metadata carried and scaled") {
  const TempDir dir;
  struct Case {
    int width, height, colour, depth;
    std::string compression;
    bool half = false, full_float = false;
    int resolution_unit = -1;
    std::vector<std::pair<std::string, std::string>> text = {};
    bool profile = false;
  };
  const std::vector<Case> cases = {
      {1, 1, PNG_COLOR_TYPE_RGB, 8, ""},
      {17, 5, PNG_COLOR_TYPE_RGB, 8, "piz", false, false, PNG_RESOLUTION_METER},
      {33, 7, PNG_COLOR_TYPE_GRAY, 8, "none", false, false, PNG_RESOLUTION_UNKNOWN},
      {20, 6, PNG_COLOR_TYPE_RGB, 16, "rle"},
      {9, 9, PNG_COLOR_TYPE_GRAY, 16, "zips"},
      {12, 8, PNG_COLOR_TYPE_PALETTE, 8, "zip"},
      {64, 40, PNG_COLOR_TYPE_RGB, 8, "zip"},  // large enough for zlib's levels to differ
      {19, 6, PNG_COLOR_TYPE_RGB_ALPHA, 8, "pxr24"},
      {7, 5, PNG_COLOR_TYPE_RGB_ALPHA, 16, "b44", true},
      {10, 4, PNG_COLOR_TYPE_GRAY_ALPHA, 8, "b44a", false, true},
      {40, 36, PNG_COLOR_TYPE_RGB, 8, "dwaa:5", false, false, PNG_RESOLUTION_METER, {{"Copyright", "c"}}, true},
      {40, 36, PNG_COLOR_TYPE_RGB_ALPHA, 8, "dwab"},
      {24, 20, PNG_COLOR_TYPE_GRAY, 8, "dwaa:200"},  // one channel: zip, as OpenImageIO writes it
      {15, 4, PNG_COLOR_TYPE_RGB, 8, "", false, false, PNG_RESOLUTION_METER,
       {{"Author", "A. Painter"}, {"Software", "dropped"}, {"Copyright", "(c) 2026"}, {"title", "Scan 3"},
        {"Description", "a test"}, {"Exif:ImageHistory", "made here"}, {"Comment", "dropped too"}}},
  };
  for (const Case& c : cases) {
    CAPTURE(c.width);
    CAPTURE(c.compression);
    PngRecipe r;
    r.width = c.width, r.height = c.height, r.colour = c.colour, r.depth = c.depth;
    r.resolution_unit = c.resolution_unit, r.text = c.text, r.profile = c.profile;
    r.time = true;  // else each writer stamps its own second
    make_png(dir / "in.png", r);
    const ImageFile file = read_image(dir / "in.png");
    const int out_w = c.width * 3, out_h = c.height * 2;
    Image image = awkward_values(out_w, out_h, file.image.channels, unsigned(c.width));
    add_half_boundaries(image);
    EncodeOptions encode;
    encode.compression = c.compression;
    encode.half = c.half;
    encode.full_float = c.full_float;
    write_through_pipeline(dir / "in.png", dir / "native.exr", image, encode);
    const auto attributes = scaled_metadata(file.metadata, 3.0, 2.0);
    write_image(dir / "oiio.exr", image, file.format, file.alpha_channel, &attributes, encode);
    CHECK(bytes_of(dir / "native.exr") == bytes_of(dir / "oiio.exr"));
  }
}

TEST_CASE("ExrWriter: without a time, the local time of writing, as OpenImageIO stamps it") {
  const TempDir dir;
  auto now = [] {
    const std::time_t t = std::time(nullptr);
    std::tm local{};
    localtime_r(&t, &local);
    char text[64];
    std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &local);
    return std::string(text);
  };
  const std::string before = now();
  {
    StagedOutput stage(dir / "o.exr");
    const int file = stage.create("o.exr");
    ExrWriter writer(stage, file, dir / "o.exr", 4, 3, 3, -1, SampleFormat::uint8, ExrMetadata{}, EncodeOptions{});
    const std::vector<float> rows(4 * 3 * 3, 0.25f);
    writer.write(rows.data(), 3);
    writer.finish();
    stage.finish(file);
    stage.commit({"o.exr"});
  }
  const std::string after = now();
  auto in = OIIO::ImageInput::open(dir / "o.exr");
  REQUIRE(in);
  const std::string stamped = in->spec().get_string_attribute("DateTime");
  CHECK(stamped >= before);
  CHECK(stamped <= after);
  CHECK(in->spec().format == OIIO::TypeDesc::HALF);
  const ImageFile back = read_image(dir / "o.exr");
  CHECK(back.image.pixels == std::vector<float>(4 * 3 * 3, 0.25f));
}

TEST_CASE("exr_writes: scanline EXRs of 1 to 4 channels with plain text, the rest left to OpenImageIO") {
  const ExrMetadata none;
  const EncodeOptions plain;
  CHECK(exr_writes("a.exr", 10, 10, 3, SampleFormat::uint8, none, plain));
  CHECK(exr_writes("A.EXR", 10, 10, 1, SampleFormat::uint16, none, plain));
  CHECK(exr_writes("a.exr", 10, 10, 4, SampleFormat::uint8, none, plain));
  CHECK_FALSE(exr_writes("a.exr", 10, 10, 5, SampleFormat::uint8, none, plain));
  CHECK_FALSE(exr_writes("a.png", 10, 10, 3, SampleFormat::uint8, none, plain));
  EncodeOptions tiled;
  tiled.tile = 64;
  CHECK_FALSE(exr_writes("a.exr", 10, 10, 3, SampleFormat::uint8, none, tiled));
  EncodeOptions bad;
  bad.compression = "zip:5";  // only DWA takes a level
  CHECK_FALSE(exr_writes("a.exr", 10, 10, 3, SampleFormat::uint8, none, bad));
  ExrMetadata text;
  text.text = {{"Artist", "a"}, {"Exif:ImageHistory", "b"}, {"GPS:Note", "c"}, {"IPTC:a:b", "d"}};
  CHECK(exr_writes("a.exr", 10, 10, 3, SampleFormat::uint8, text, plain));
  for (const char* special : {"Software", "name", "compression", "type", "tiff:Note", "oiio:ColorSpace"}) {
    CAPTURE(special);
    ExrMetadata odd;
    odd.text = {{special, "x"}};
    CHECK_FALSE(exr_writes("a.exr", 10, 10, 3, SampleFormat::uint8, odd, plain));
  }
}
