// The file job of the command line and of Python's upscale_file
// (pipeline/file_upscale.hpp): the file it writes is the enlargement
// written whole, bit for bit, streamed or read by bands; I/O failures are
// FileError, the rest ddt::Error, and nothing is left behind on failure.

#include "../test_support.hpp"
#include "eval/synthetic_scenes.hpp"
#include "io/image_io.hpp"
#include "pipeline/file_upscale.hpp"
#include "pipeline/upscale.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <random>

using namespace ddt;
using ddt::test::TempDir;

namespace {

Image noisy_scene(int w, int h) {
  Image img = render_scene(find_scene("colour_regions"), w, h);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> noise(0.0f, 0.1f);
  for (float& v : img.pixels) v = std::clamp(v + noise(rng), 0.0f, 1.0f);
  return img;
}

FileUpscaleJob job_of(const std::string& in, const std::string& out, double scale) {
  FileUpscaleJob job;
  job.input = in;
  job.output = out;
  job.size.scale = scale;
  job.size.max_pixels = default_max_pixels;
  return job;
}

}  // namespace

TEST_CASE("upscale_file: the file written equals the enlargement written whole, streamed or read by bands") {
  const TempDir dir;
  write_image(dir / "in.png", noisy_scene(64, 256), SampleFormat::uint8);
  const ImageFile in = read_image(dir / "in.png");
  for (const char* model : {"box", "point"}) {
    CAPTURE(model);
    UpscaleOptions options;
    options.model = parse_acquisition_model(model);
    options.region_rows = 16;
    options.tile_rows = -1;
    write_image(dir / "whole.png", upscale(in.image, 128, 512, options), SampleFormat::uint8);
    const Image whole = read_image(dir / "whole.png").image;

    FileUpscaleJob streamed = job_of(dir / "in.png", dir / "streamed.png", 2);
    streamed.options = options;
    const FileUpscaleResult s = upscale_file(streamed);
    CHECK(s.width == 128);
    CHECK(s.height == 512);
    CHECK(s.bands == 0);
    CHECK(read_image(dir / "streamed.png").image.pixels == whole.pixels);

    FileUpscaleJob banded = job_of(dir / "in.png", dir / "banded.png", 2);
    banded.options = options;
    banded.options.tile_rows = 48;
    const FileUpscaleResult b = upscale_file(banded);
    CHECK(b.bands == 6);
    CHECK(read_image(dir / "banded.png").image.pixels == whole.pixels);
  }
}

TEST_CASE("upscale_file: a file that cannot be read or written is a FileError, a bad size an Error - nothing is left") {
  const TempDir dir;
  write_image(dir / "in.png", noisy_scene(16, 16), SampleFormat::uint8);
  CHECK_THROWS_AS(upscale_file(job_of(dir / "missing.png", dir / "out.png", 2)), FileError);
  CHECK_THROWS_AS(upscale_file(job_of(dir / "in.png", dir / "in.png", 2)), FileError);
  CHECK_THROWS_AS(upscale_file(job_of(dir / "in.png", dir / "no/such/dir/out.png", 2)), FileError);
  FileUpscaleJob too_large = job_of(dir / "in.png", dir / "out.png", 100);
  too_large.size.max_pixels = 1000;
  try {
    upscale_file(too_large);
    FAIL("an output over max_pixels was accepted");
  } catch (const FileError& e) {
    FAIL("a size refusal reported as a file error: " << e.what());
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("pixels") != std::string::npos);
  }
  CHECK_FALSE(std::filesystem::exists(dir / "out.png"));
  CHECK(std::distance(std::filesystem::directory_iterator(dir.path), std::filesystem::directory_iterator()) == 1);
}
