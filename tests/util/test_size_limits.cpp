// The size limits (size_limits.hpp) and the readers that apply them from a
// file's header, before any sample is decoded.
#include "util/error.hpp"
#include "io/image_io.hpp"
#include "scattered/point_table.hpp"
#include "util/size_limits.hpp"
#include "test_support.hpp"
#include "io/volume_io.hpp"

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

using namespace ddt;
namespace fs = std::filesystem;

using test::TempDir;

TEST_CASE("checked_product and check_size_limit: the count, its overflow, the message") {
  CHECK(checked_product({3, 5, 7}) == 105);
  CHECK(checked_product({}) == 1);
  CHECK(checked_product({1LL << 32, 1LL << 31}) == -1);  // 2^63 passes a long long
  CHECK(checked_product({1LL << 32, (1LL << 31) - 1}) == (1LL << 32) * ((1LL << 31) - 1));
  CHECK(checked_product({-1, 4}) == -1);
  CHECK_NOTHROW(check_size_limit("input 'a'", "10x10", 100, 100, "--max"));
  CHECK_THROWS_WITH_AS(check_size_limit("input 'a'", "10x11", 110, 100, "--max"),
                       "input 'a' 10x11 exceeds --max 100; give --max 110 to allow it", Error);
  // A count past 2^63 names no value to give.
  CHECK_THROWS_WITH_AS(check_size_limit("input 'a'", "huge", -1, std::numeric_limits<long long>::max(), "--max"),
                       ("input 'a' huge exceeds --max " + std::to_string(std::numeric_limits<long long>::max())).c_str(),
                       Error);
}

TEST_CASE("memory: physical and available are positive, a job past them is refused, defaults follow the memory") {
  CHECK(physical_memory() > 0);
  CHECK(available_memory() > 0);
  CHECK_NOTHROW(check_memory_fits("a small job", 1e6));
  CHECK_THROWS_AS(check_memory_fits("a huge job", 4.0 * double(physical_memory()) + 1e12), Error);
  CHECK(default_max_input_pixels() == physical_memory() / 32);
  CHECK(default_max_input_voxels() == physical_memory() / 1024);
}

TEST_CASE("parse_memory_size: bytes and K, M, G, T in powers of 1024 - one-line errors for the rest") {
  CHECK(parse_memory_size("1500000000") == 1500000000LL);
  CHECK(parse_memory_size("512M") == 512LL << 20);
  CHECK(parse_memory_size("2G") == 2LL << 30);
  CHECK(parse_memory_size("2g") == 2LL << 30);
  CHECK(parse_memory_size("2GB") == 2LL << 30);
  CHECK(parse_memory_size("2GiB") == 2LL << 30);
  CHECK(parse_memory_size("1.5G") == 3LL << 29);
  CHECK(parse_memory_size("64K") == 65536);
  CHECK(parse_memory_size("1T") == 1LL << 40);
  CHECK(parse_memory_size("100B") == 100);
  for (const char* bad : {"", "x", "0", "-1", "1.5", "2Q", "G", "2 G", "1.5B", "1e30", "nan", "inf", "2GG", "9999999T"})
    CHECK_THROWS_WITH_AS(parse_memory_size(bad), doctest::Contains("is not a memory size"), Error);
  CHECK(resident_memory() > 0);
}

TEST_CASE("read_image: the header's size is checked against the limit before the pixels, then the check sees it") {
  TempDir dir;
  Image image(40, 30, 3, 0.25f);
  write_image(dir / "a.png", image, SampleFormat::uint8);
  ImageReadLimits limits;
  limits.max_pixels = 40 * 30 - 1;
  CHECK_THROWS_WITH_AS(read_image(dir / "a.png", limits),
                       ("input '" + (dir / "a.png") + "' 40x30 exceeds --max-input-pixels 1199; give --max-input-pixels 1200 to allow it").c_str(), Error);
  limits.max_pixels = 40 * 30;
  ImageHeader seen;
  limits.check = [&](const ImageHeader& header) { seen = header; };
  const ImageFile file = read_image(dir / "a.png", limits);
  CHECK(seen.width == 40);
  CHECK(seen.height == 30);
  CHECK(seen.channels == 3);
  CHECK(seen.format == SampleFormat::uint8);
  CHECK(file.image.width == 40);
  // A check that throws stops the read (the CLI refuses its job there).
  limits.check = [](const ImageHeader&) { throw Error("refused from the header"); };
  CHECK_THROWS_WITH_AS(read_image(dir / "a.png", limits), "refused from the header", Error);
}

TEST_CASE("read_volume: the header's voxel count is checked before the data file is read") {
  TempDir dir;
  write_volume(dir / "v.nhdr", Volume(4, 5, 6, 1.0f), VolumeSampleType::uint8, VolumeEncoding::raw);
  VolumeReadOptions options;
  options.max_voxels = 119;
  CHECK_THROWS_WITH_AS(read_volume(dir / "v.nhdr", options),
                       ("input '" + (dir / "v.nhdr") + "' 4x5x6 exceeds --max-input-voxels 119; give --max-input-voxels 120 to allow it").c_str(), Error);
  // The data file is not opened for the refusal: a header that claims 2^60
  // voxels of a data file that holds nothing is refused by its claim (with
  // no hint to allow it: no machine holds 2^60 voxels).
  std::ofstream(dir / "bomb.nhdr") << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1048576 1048576 1048576\n"
                                      "encoding: raw\ndata file: empty.raw\n";
  std::ofstream(dir / "empty.raw").flush();
  options.max_voxels = default_max_input_voxels();
  CHECK_THROWS_WITH_AS(read_volume(dir / "bomb.nhdr", options),
                       ("input '" + (dir / "bomb.nhdr") + "' 1048576x1048576x1048576 exceeds --max-input-voxels " +
                        std::to_string(default_max_input_voxels()))
                           .c_str(),
                       Error);
  options.max_voxels = 120;
  int seen[4] = {0, 0, 0, 0};
  options.check = [&](const std::array<int, 4>& size, int channels) { seen[0] = size[0], seen[1] = size[1], seen[2] = size[2], seen[3] = channels; };
  const VolumeFile file = read_volume(dir / "v.nhdr", options);
  CHECK(seen[0] == 4);
  CHECK(seen[1] == 5);
  CHECK(seen[2] == 6);
  CHECK(seen[3] == 1);
  CHECK(file.volume.voxel_count() == 120);
}

TEST_CASE("read_volume: data file names are read from the header's text, as Teem reads them") {
  TempDir dir;
  write_volume(dir / "a.nhdr", Volume(2, 2, 2, 3.0f), VolumeSampleType::uint8, VolumeEncoding::raw);
  std::ofstream(dir / "list.nhdr") << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                                      "data file: LIST 3\na.raw\n";
  CHECK(volume_files(dir / "list.nhdr") == std::vector<std::string>{dir / "list.nhdr", dir / "a.raw"});
  std::ofstream(dir / "s1.raw") << std::string(4, '\1');
  std::ofstream(dir / "s2.raw") << std::string(4, '\2');
  std::ofstream(dir / "pattern.nhdr") << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                                         "data file: s%d.raw 1 2 1 2\n";
  CHECK(volume_files(dir / "pattern.nhdr") ==
        std::vector<std::string>{dir / "pattern.nhdr", dir / "s1.raw", dir / "s2.raw"});
  const VolumeFile file = read_volume(dir / "pattern.nhdr");
  CHECK(file.volume.voxels[0] == 1.0f);
  CHECK(file.volume.voxels[7] == 2.0f);
}

TEST_CASE("read_point_table: more points than the limit are refused at the line that passes it") {
  std::istringstream in("x,y,v\n0,0,1\n1,0,2\n0,1,3\n1,1,4\n");
  PointReadOptions options;
  options.max_points = 3;
  CHECK_THROWS_WITH_AS(parse_point_table(in, "p.csv", options),
                       "cannot read 'p.csv', line 5: more than 3 points (--max-input-points)", Error);
  std::istringstream again("x,y,v\n0,0,1\n1,0,2\n0,1,3\n");
  CHECK(parse_point_table(again, "p.csv", options).points.size() == 3);
}
