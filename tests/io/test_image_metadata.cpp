// Metadata a photographer expects kept (issue 20, item 12): ICC profile,
// EXIF with its orientation, resolution scaled, and the pages a file holds.
#include "io/image_io.hpp"
#include "test_support.hpp"

#include <OpenImageIO/imageio.h>
#include <doctest/doctest.h>

#include <cstring>
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
    if (std::string(ext) == "jpg") CHECK(spec.get_string_attribute("Exif:DateTimeOriginal") == "2020:01:02 03:04:05");
  }
  // The EXIF pixel dimensions describe the input: dropped.
  OIIO::ParamValueList with_size = file.metadata;
  with_size.attribute("Exif:PixelXDimension", 6);
  const OIIO::ParamValueList scaled = scaled_metadata(with_size, 2, 2);
  CHECK_FALSE(scaled.contains("Exif:PixelXDimension"));
  CHECK(scaled.contains("Make"));
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
