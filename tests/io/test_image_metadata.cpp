// Metadata a photographer expects kept (issue 20, item 12): ICC profile,
// EXIF and GPS with the orientation, resolution scaled, EXR windows, and the
// pages a file holds.
#include "io/image_io.hpp"
#include "test_support.hpp"

#include <OpenImageIO/imageio.h>
#include <doctest/doctest.h>
#include <lcms2.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

using namespace ddt;
using test::TempDir;

namespace {

// A 132-byte ICC header (no tags): enough for JPEG and TIFF to carry, not a
// profile libpng accepts (PNG's ICC is not checked here).
std::vector<unsigned char> icc_header() {
  std::vector<unsigned char> p(132, 0);
  auto be32 = [&](int at, unsigned v) {
    for (int k = 0; k < 4; ++k) p[at + k] = static_cast<unsigned char>(v >> (24 - 8 * k));
  };
  be32(0, 132);
  be32(8, 0x02100000);
  std::memcpy(&p[12], "mntr", 4);
  std::memcpy(&p[16], "RGB ", 4);
  std::memcpy(&p[20], "XYZ ", 4);
  std::memcpy(&p[36], "acsp", 4);
  return p;
}

// A 6x4 JPEG with a distinct top-left pixel, orientation 6 (stored rotated:
// displayed turned 90 degrees clockwise), 300 dpi, an ICC header and EXIF.
void write_photo(const std::string& path, const std::vector<unsigned char>& icc) {
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(6, 4, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("ICCProfile", OIIO::TypeDesc(OIIO::TypeDesc::UINT8, static_cast<int>(icc.size())), icc.data());
  spec.attribute("Orientation", 6);
  spec.attribute("XResolution", 300.0f);
  spec.attribute("YResolution", 300.0f);
  spec.attribute("ResolutionUnit", "in");
  spec.attribute("Make", "TestCam");
  spec.attribute("Exif:DateTimeOriginal", "2020:01:02 03:04:05");
  spec.attribute("GPS:LatitudeRef", "N");
  std::vector<float> pixels(6 * 4 * 3, 0.0f);
  pixels[0] = pixels[1] = pixels[2] = 1.0f;
  REQUIRE(out->open(path, spec));
  REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  REQUIRE(out->close());
}

}  // namespace

TEST_CASE("metadata: ICC, EXIF and orientation carried by JPEG and TIFF, orientation applied in PNG and EXR") {
  TempDir dir;
  const std::vector<unsigned char> icc = icc_header();
  write_photo(dir / "photo.jpg", icc);
  const ImageFile file = read_image(dir / "photo.jpg");
  CHECK(file.pages == 1);
  const OIIO::ParamValueList metadata = scaled_metadata(file.metadata, 2.0, 2.0);
  Image big(12, 8, 3, 0.0f);
  big.pixels[0] = big.pixels[1] = big.pixels[2] = 1.0f;  // the stored top-left corner
  for (const char* ext : {"jpg", "tif", "png", "exr"}) {
    CAPTURE(ext);
    const std::string path = dir / (std::string("out.") + ext);
    write_image(path, big, file.format, -1, &metadata);
    auto in = OIIO::ImageInput::open(path);
    REQUIRE(in);
    const OIIO::ImageSpec& spec = in->spec();
    CHECK(spec.get_float_attribute("XResolution") == doctest::Approx(600.0).epsilon(1e-4));  // same printed size
    CHECK(spec.get_string_attribute("Make") == "TestCam");
    const bool carries = std::string(ext) == "jpg" || std::string(ext) == "tif";
    if (carries) {
      CHECK(spec.get_int_attribute("Orientation") == 6);
      CHECK(spec.width == 12);
      const OIIO::ParamValue* profile = spec.find_attribute("ICCProfile");
      REQUIRE(profile);
      CHECK(profile->type().size() == icc.size());
      CHECK(std::memcmp(profile->data(), icc.data(), icc.size()) == 0);
    } else {
      // Applied: stored 12x8 turned 90 degrees clockwise is 8x12 upright,
      // the stored top-left corner now at the top right.
      CHECK(spec.get_int_attribute("Orientation", 1) == 1);
      REQUIRE(spec.width == 8);
      REQUIRE(spec.height == 12);
      std::vector<float> px(8 * 12 * 3);
      REQUIRE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data()));
      CHECK(px[(0 * 8 + 7) * 3] > 0.5f);
      CHECK(px[0] < 0.5f);
    }
    if (carries) CHECK(spec.get_string_attribute("Exif:DateTimeOriginal") == "2020:01:02 03:04:05");
    // OpenImageIO 2.4's TIFF writer writes no GPS directory at all.
    if (std::string(ext) == "jpg") CHECK(spec.get_string_attribute("GPS:LatitudeRef") == "N");
  }
  // The TIFF with EXIF was written by path in the private directory: nothing
  // of it is left beside the outputs.
  for (const auto& entry : std::filesystem::directory_iterator(dir.path))
    CHECK(entry.path().filename().string().rfind(".ddtscale-", 0) != 0);
  // The EXIF pixel dimensions describe the input: dropped.
  OIIO::ParamValueList with_size = file.metadata;
  with_size.attribute("Exif:PixelXDimension", 6);
  const OIIO::ParamValueList scaled = scaled_metadata(with_size, 2, 2);
  CHECK_FALSE(scaled.contains("Exif:PixelXDimension"));
  CHECK(scaled.contains("Make"));
}

namespace {

// A valid ICC v4 RGB display profile made by Little CMS: D65 white, Display
// P3's primaries, gamma 2.2 (a profile libpng checks and accepts).
std::vector<unsigned char> p3_profile() {
  const cmsCIExyY white = {0.3127, 0.3290, 1.0};
  const cmsCIExyYTRIPLE primaries = {{0.680, 0.320, 1.0}, {0.265, 0.690, 1.0}, {0.150, 0.060, 1.0}};
  cmsToneCurve* gamma = cmsBuildGamma(nullptr, 2.2);
  cmsToneCurve* curves[3] = {gamma, gamma, gamma};
  cmsHPROFILE profile = cmsCreateRGBProfile(&white, &primaries, curves);
  cmsFreeToneCurve(gamma);
  REQUIRE(profile);
  cmsUInt32Number size = 0;
  REQUIRE(cmsSaveProfileToMem(profile, nullptr, &size));
  std::vector<unsigned char> bytes(size);
  REQUIRE(cmsSaveProfileToMem(profile, bytes.data(), &size));
  cmsCloseProfile(profile);
  return bytes;
}

std::vector<unsigned char> icc_of(const OIIO::ImageSpec& spec) {
  const OIIO::ParamValue* p = spec.find_attribute("ICCProfile");
  if (!p) return {};
  const auto* bytes = static_cast<const unsigned char*>(p->data());
  return {bytes, bytes + p->type().size()};
}

}  // namespace

TEST_CASE("metadata: a valid ICC profile in a PNG, TIFF or JPEG is carried byte for byte to each of them") {
  TempDir dir;
  const std::vector<unsigned char> icc = p3_profile();
  REQUIRE(icc.size() > 132);
  for (const char* in_ext : {"png", "tif", "jpg"}) {
    const std::string input = dir / (std::string("in.") + in_ext);
    {
      auto out = OIIO::ImageOutput::create(input);
      OIIO::ImageSpec spec(6, 4, 3, OIIO::TypeDesc::UINT8);
      spec.attribute("ICCProfile", OIIO::TypeDesc(OIIO::TypeDesc::UINT8, static_cast<int>(icc.size())), icc.data());
      const std::vector<float> pixels(6 * 4 * 3, 0.25f);
      REQUIRE(out->open(input, spec));
      REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
      REQUIRE(out->close());
    }
    const ImageFile file = read_image(input);
    const OIIO::ParamValueList metadata = scaled_metadata(file.metadata, 2.0, 2.0);
    const Image big(12, 8, 3, 0.25f);
    for (const char* out_ext : {"png", "tif", "jpg"}) {
      CAPTURE(in_ext);
      CAPTURE(out_ext);
      const std::string output = dir / (std::string("out.") + out_ext);
      write_image(output, big, file.format, -1, &metadata);
      auto in = OIIO::ImageInput::open(output);
      REQUIRE(in);
      CHECK(in->spec().width == 12);
      CHECK(icc_of(in->spec()) == icc);
    }
  }
}

TEST_CASE("metadata: an EXR's data and display windows are kept, scaled, on EXR output") {
  TempDir dir;
  // A 6x4 data window at (3, 2) in a 10x8 display window from (-1, 0).
  OIIO::ImageSpec spec(6, 4, 1, OIIO::TypeDesc::FLOAT);
  spec.x = 3, spec.y = 2;
  spec.full_x = -1, spec.full_y = 0, spec.full_width = 10, spec.full_height = 8;
  {
    auto out = OIIO::ImageOutput::create(dir / "in.exr");
    const std::vector<float> pixels(6 * 4, 0.5f);
    REQUIRE(out->open(dir / "in.exr", spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    REQUIRE(out->close());
  }
  const ImageFile file = read_image(dir / "in.exr");
  CHECK(file.image.width == 6);
  CHECK(file.image.height == 4);
  struct Case {
    double sx, sy;
    int x, y, full_x, full_y, full_width, full_height;
  };
  // Corners where the enlargement maps them: x3 by x2 maps (3, 2) to (9, 4)
  // and the display window to (-3, 0) 30x16; x2.5 by x1.5 rounds 7.5 and
  // -2.5 up.
  for (const Case& c : {Case{3, 2, 9, 4, -3, 0, 30, 16}, Case{2.5, 1.5, 8, 3, -2, 0, 25, 12}}) {
    CAPTURE(c.sx);
    const int w = static_cast<int>(std::lround(6 * c.sx)), h = static_cast<int>(std::lround(4 * c.sy));
    const OIIO::ParamValueList metadata = scaled_metadata(file.metadata, double(w) / 6, double(h) / 4);
    write_image(dir / "out.exr", Image(w, h, 1, 0.5f), file.format, -1, &metadata);
    auto in = OIIO::ImageInput::open(dir / "out.exr");
    REQUIRE(in);
    const OIIO::ImageSpec& got = in->spec();
    CHECK(got.width == w);
    CHECK(got.height == h);
    CHECK(got.x == c.x);
    CHECK(got.y == c.y);
    CHECK(got.full_x == c.full_x);
    CHECK(got.full_y == c.full_y);
    CHECK(got.full_width == c.full_width);
    CHECK(got.full_height == c.full_height);
    // Formats without windows get the pixels alone.
    write_image(dir / "out.png", Image(w, h, 1, 0.5f), file.format, -1, &metadata);
    auto png = OIIO::ImageInput::open(dir / "out.png");
    REQUIRE(png);
    CHECK(png->spec().x == 0);
    CHECK(png->spec().width == w);
  }
  // An image whose data window is its display window carries no windows.
  write_image(dir / "plain.exr", Image(6, 4, 1, 0.5f), SampleFormat::float32);
  CHECK_FALSE(read_image(dir / "plain.exr").metadata.contains("ddtscale:data_origin"));
}

TEST_CASE("metadata: a TIFF's pages are counted (only the first is read)") {
  TempDir dir;
  auto out = OIIO::ImageOutput::create(dir / "two.tif");
  REQUIRE(out->supports("multiimage"));
  const OIIO::ImageSpec specs[2] = {OIIO::ImageSpec(4, 4, 1, OIIO::TypeDesc::UINT8),
                                    OIIO::ImageSpec(3, 5, 1, OIIO::TypeDesc::UINT8)};
  REQUIRE(out->open(dir / "two.tif", 2, specs));
  std::vector<float> pixels(4 * 5, 0.5f);
  REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  REQUIRE(out->open(dir / "two.tif", specs[1], OIIO::ImageOutput::AppendSubimage));
  REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  REQUIRE(out->close());
  const ImageFile file = read_image(dir / "two.tif");
  CHECK(file.pages == 2);
  CHECK(file.image.width == 4);
  CHECK(file.image.height == 4);
}
