#include "io/frame_sequence.hpp"
#include "util/error.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

using namespace ddt;
namespace fs = std::filesystem;

namespace {

struct ScratchDir {
  fs::path path;
  ScratchDir() {
    std::string name = (fs::temp_directory_path() / "ddtscale-frames-XXXXXX").string();
    REQUIRE(::mkdtemp(name.data()));
    path = name;
  }
  ~ScratchDir() { fs::remove_all(path); }
};

Image grey(int w, int h, float v) { return Image(w, h, 1, v); }

}  // namespace

TEST_CASE("frame patterns: %d and %0Nd, names written and recognized as printf would") {
  const FramePattern p = parse_frame_pattern("shot/in_%04d.png");
  CHECK(p.directory == "shot");
  CHECK(p.file_name(7) == "in_0007.png");
  CHECK(p.file_name(123456) == "in_123456.png");
  CHECK(p.path(12) == "shot/in_0012.png");
  CHECK(p.number_of("in_0012.png") == 12);
  CHECK(p.number_of("in_12.png") == -1);      // too few digits for %04d
  CHECK(p.number_of("in_00012.png") == -1);   // a leading zero %04d would not write
  CHECK(p.number_of("in_12345.png") == 12345);
  CHECK(p.number_of("in_0012.jpg") == -1);
  const FramePattern plain = parse_frame_pattern("f%d.exr");
  CHECK(plain.file_name(0) == "f0.exr");
  CHECK(plain.number_of("f010.exr") == -1);
  CHECK(plain.number_of("f10.exr") == 10);
  CHECK(parse_frame_pattern("100%%_%03d.png").file_name(5) == "100%_005.png");
  CHECK(is_frame_pattern("a/b_%03d.tif"));
  CHECK_FALSE(is_frame_pattern("50%.png"));
  CHECK_FALSE(is_frame_pattern("plain.png"));
  for (const char* bad : {"in.png", "in_%04d_%04d.png", "in_%4d.png", "in_%00d.png", "in_%s.png", "dir%d/in_%d.png",
                          "in_%04d"})
    CHECK_THROWS_AS(parse_frame_pattern(bad), Error);
}

TEST_CASE("frame sequences: found in order - a gap, no match and mismatched frames are refused") {
  ScratchDir dir;
  const FramePattern p = parse_frame_pattern((dir.path / "f_%03d.png").string());
  CHECK_THROWS_WITH_AS(find_frames(p), doctest::Contains("matches no file"), Error);
  for (int n : {3, 4, 5}) write_image(p.path(n), grey(4, 3, 0.1f * n), SampleFormat::uint8);
  std::ofstream(dir.path / "f_04.png") << "not a frame of this pattern";
  CHECK(find_frames(p) == std::vector<int>{3, 4, 5});
  const ImageFile first = read_frame(p, 3);
  CHECK(read_frame(p, 5, &first).image.at(0, 0) == doctest::Approx(0.5).epsilon(0.01));
  write_image(p.path(6), grey(5, 3, 0.2f), SampleFormat::uint8);
  CHECK_THROWS_WITH_AS(read_frame(p, 6, &first), doctest::Contains("all frames must match"), Error);
  fs::remove(p.path(6));
  write_image(p.path(6), grey(4, 3, 0.2f), SampleFormat::uint16);
  CHECK_THROWS_WITH_AS(read_frame(p, 6, &first), doctest::Contains("16-bit"), Error);
  write_image(p.path(8), grey(4, 3, 0.2f), SampleFormat::uint8);
  CHECK_THROWS_WITH_AS(find_frames(p), doctest::Contains("frame 7"), Error);
}

TEST_CASE("FrameSequenceWriter: nothing appears before commit, nothing is left without it - inputs are kept") {
  ScratchDir dir;
  const FramePattern out = parse_frame_pattern((dir.path / "o_%02d.png").string());
  {
    FrameSequenceWriter w(out, SampleFormat::uint8, -1, nullptr, {}, {});
    w.write(1, grey(4, 4, 0.5f));
    w.write(2, grey(4, 4, 0.5f));
    CHECK_FALSE(fs::exists(out.path(1)));
  }  // no commit: removed
  CHECK(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator{}) == 0);
  {
    FrameSequenceWriter w(out, SampleFormat::uint8, -1, nullptr, {}, {});
    w.write(1, grey(4, 4, 0.5f));
    w.write(2, grey(4, 4, 0.5f));
    w.commit();
  }
  CHECK(fs::exists(out.path(1)));
  CHECK(fs::exists(out.path(2)));
  CHECK(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator{}) == 2);
  // An output frame that is an input frame is refused, and nothing replaced.
  const auto before = fs::last_write_time(out.path(1));
  FrameSequenceWriter w(out, SampleFormat::uint8, -1, nullptr, {}, {out.path(1)});
  w.write(1, grey(4, 4, 0.9f));
  CHECK_THROWS_AS(w.commit(), Error);
  CHECK(fs::last_write_time(out.path(1)) == before);
}
