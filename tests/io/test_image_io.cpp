#include "util/error.hpp"
#include "io/image_io.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

using namespace ddt;
namespace fs = std::filesystem;

namespace {
fs::path scratch_dir() {
  fs::path dir = fs::temp_directory_path() / ("ddtscale_io_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}
std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}
}  // namespace

TEST_CASE("write_image: EXR keeps float values, PNG keeps 16 bits") {
  const fs::path dir = scratch_dir();
  Image img(3, 2, 1);
  img.pixels = {0.0f, 0.123456789f, 1.5f, -0.25f, 0.5f, 1.0f};
  write_image((dir / "a.exr").string(), img, SampleFormat::float32);
  ImageFile back = read_image((dir / "a.exr").string());
  CHECK(back.format == SampleFormat::float32);
  CHECK(back.image.pixels == img.pixels);

  write_image((dir / "b.png").string(), img, SampleFormat::uint16);
  back = read_image((dir / "b.png").string());
  CHECK(back.format == SampleFormat::uint16);
  CHECK(back.image.at(1, 0) == doctest::Approx(std::round(0.123456789 * 65535) / 65535).epsilon(1e-6));
  CHECK(back.image.at(2, 0) == 1.0f);  // clamped
  CHECK(back.image.at(0, 1) == 0.0f);  // clamped
  fs::remove_all(dir);
}

TEST_CASE("read_image: missing, corrupt and empty files are one-line errors") {
  const fs::path dir = scratch_dir();
  CHECK_THROWS_AS(read_image((dir / "missing.png").string()), Error);
  std::ofstream(dir / "corrupt.png") << "this is not a png";
  try {
    read_image((dir / "corrupt.png").string());
    FAIL("corrupt file accepted");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find('\n') == std::string::npos);
  }
  CHECK_THROWS_AS(read_image(dir.string()), Error);
  fs::remove_all(dir);
}

TEST_CASE("write_image: a failed write leaves the existing file untouched") {
  const fs::path dir = scratch_dir();
  const fs::path target = dir / "keep.unknownext";
  std::ofstream(target) << "precious";
  Image img(2, 2, 1, 0.5f);
  CHECK_THROWS_AS(write_image(target.string(), img, SampleFormat::uint8), Error);
  CHECK(slurp(target) == "precious");
  const fs::path png = dir / "keep.png";
  std::ofstream(png) << "precious";
  CHECK_THROWS_AS(write_image(png.string(), Image{}, SampleFormat::uint8), Error);
  CHECK(slurp(png) == "precious");
  // No temporary files are left behind.
  int files = 0;
  for ([[maybe_unused]] auto& entry : fs::directory_iterator(dir)) ++files;
  CHECK(files == 2);
  fs::remove_all(dir);
}

TEST_CASE("check_output_path: refuses the input itself and missing directories") {
  const fs::path dir = scratch_dir();
  const fs::path in = dir / "in.png";
  write_image(in.string(), Image(2, 2, 1, 0.5f), SampleFormat::uint8);
  CHECK_THROWS_AS(check_output_path(in.string(), in.string()), Error);
  CHECK_THROWS_AS(check_output_path((dir / "." / "in.png").string(), in.string()), Error);
  CHECK_THROWS_AS(check_output_path((dir / "nope" / "out.png").string(), in.string()), Error);
  CHECK_THROWS_AS(check_output_path(dir.string(), in.string()), Error);
  CHECK_NOTHROW(check_output_path((dir / "out.exr").string(), in.string()));
  fs::remove_all(dir);
}
