#include "util/error.hpp"
#include "test_support.hpp"
#include "io/volume_io.hpp"

#include <doctest/doctest.h>

#include <teem/nrrd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

using namespace ddt;
namespace fs = std::filesystem;

namespace {

using test::TempDir;

Volume ramp(int nx, int ny, int nz, double scale) {
  Volume v(nx, ny, nz);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) v.at(x, y, z) = static_cast<float>(scale * (x + 2 * y + 3 * z) / (nx + 2 * ny + 3 * nz));
  return v;
}

// A NRRD with world geometry, written by Teem directly (not by write_volume).
void write_geometric_nrrd(const std::string& path, const Volume& v) {
  Nrrd* n = nrrdNew();
  std::vector<unsigned short> data(v.voxel_count());
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<unsigned short>(v.voxels[i]);
  REQUIRE(nrrdWrap_va(n, data.data(), nrrdTypeUShort, 3, std::size_t(v.nx), std::size_t(v.ny), std::size_t(v.nz)) == 0);
  n->space = nrrdSpaceRightAnteriorSuperior;
  n->spaceDim = 3;
  const double dirs[3][3] = {{0.5, 0, 0}, {0, 0.6, 0}, {0, 0, 2.0}};
  for (int a = 0; a < 3; ++a) {
    for (int d = 0; d < 3; ++d) n->axis[a].spaceDirection[d] = dirs[a][d];
    n->axis[a].center = nrrdCenterCell;
  }
  n->spaceOrigin[0] = 10, n->spaceOrigin[1] = -5, n->spaceOrigin[2] = 1;
  nrrdKeyValueAdd(n, "modality", "CT");
  NrrdIoState* nio = nrrdIoStateNew();
  nio->encoding = nrrdEncodingGzip;
  REQUIRE(nrrdSave(path.c_str(), n, nio) == 0);
  nrrdIoStateNix(nio);
  nrrdNix(n);
}

}  // namespace

TEST_CASE("write_volume / read_volume: every sample type and encoding round-trips and keeps its type") {
  TempDir dir;
  for (VolumeSampleType type : {VolumeSampleType::uint8, VolumeSampleType::int8, VolumeSampleType::uint16,
                                VolumeSampleType::int16, VolumeSampleType::int32, VolumeSampleType::float32,
                                VolumeSampleType::float64}) {
    for (VolumeEncoding enc : {VolumeEncoding::raw, VolumeEncoding::gzip}) {
      const std::string name = std::string(sample_type_name(type)) + "-" + encoding_name(enc) + ".nrrd";
      CAPTURE(name);
      const Volume v = ramp(5, 4, 3, type == VolumeSampleType::int8 ? 100 : 250);
      write_volume(dir / name, v, type, enc);
      const VolumeFile f = read_volume(dir / name);
      CHECK(f.type == type);
      CHECK(f.encoding == enc);
      REQUIRE(f.volume.nx == 5);
      REQUIRE(f.volume.ny == 4);
      REQUIRE(f.volume.nz == 3);
      const bool integer = type != VolumeSampleType::float32 && type != VolumeSampleType::float64;
      for (std::size_t i = 0; i < v.voxels.size(); ++i)
        CHECK(f.volume.voxels[i] == (integer ? std::nearbyint(v.voxels[i]) : v.voxels[i]));
    }
  }
}

TEST_CASE("write_volume: integer output is rounded and clamped to the type's range") {
  TempDir dir;
  Volume v(3, 1, 1);
  v.voxels = {-7.6f, 100.5f, 300.2f};
  write_volume(dir / "u8.nrrd", v, VolumeSampleType::uint8, VolumeEncoding::raw);
  const VolumeFile f = read_volume(dir / "u8.nrrd");
  CHECK(f.volume.voxels == std::vector<float>{0.f, 100.f, 255.f});  // 100.5 rounds to even
}

TEST_CASE("write_volume: spacing, directions and origin are scaled so samples keep their world position") {
  TempDir dir;
  const Volume v = ramp(4, 5, 6, 1000);
  write_geometric_nrrd(dir / "geo.nrrd", v);
  const VolumeFile in = read_volume(dir / "geo.nrrd");
  CHECK(in.type == VolumeSampleType::uint16);
  CHECK(in.encoding == VolumeEncoding::gzip);
  const Volume big(16, 10, 6);  // x4, x2, x1
  write_volume(dir / "big.nrrd", big, in.type, in.encoding, in.header.get(), "test");
  Nrrd* n = nrrdNew();
  REQUIRE(nrrdLoad(n, (dir / "big.nrrd").c_str(), nullptr) == 0);
  CHECK(n->type == nrrdTypeUShort);
  CHECK(n->space == nrrdSpaceRightAnteriorSuperior);
  CHECK(n->axis[0].spaceDirection[0] == doctest::Approx(0.125));
  CHECK(n->axis[1].spaceDirection[1] == doctest::Approx(0.3));
  CHECK(n->axis[2].spaceDirection[2] == doctest::Approx(2.0));
  // Output sample X sits at input index (X + 0.5) / s - 0.5: the first at -0.375 (x4), -0.25 (x2), 0 (x1).
  CHECK(n->spaceOrigin[0] == doctest::Approx(10 - 0.375 * 0.5));
  CHECK(n->spaceOrigin[1] == doctest::Approx(-5 - 0.25 * 0.6));
  CHECK(n->spaceOrigin[2] == doctest::Approx(1.0));
  char* modality = nrrdKeyValueGet(n, "modality");  // Teem returns a copy we must free
  REQUIRE(modality != nullptr);
  CHECK(std::string(modality) == "CT");
  free(modality);
  nrrdNuke(n);
}

TEST_CASE("write_volume: a detached header (.nhdr) names its data file, written atomically beside it") {
  TempDir dir;
  const Volume v = ramp(3, 3, 3, 10);
  write_volume(dir / "d.nhdr", v, VolumeSampleType::float32, VolumeEncoding::gzip);
  CHECK(fs::exists(dir / "d.nhdr"));
  CHECK(fs::exists(dir / "d.raw.gz"));
  const VolumeFile f = read_volume(dir / "d.nhdr");
  CHECK(f.volume.voxels == v.voxels);
  for (const auto& entry : fs::directory_iterator(dir.path))  // no temporary left behind
    CHECK(entry.path().filename().string().rfind(".ddtscale-", 0) != 0);
}

TEST_CASE("read_volume: bad files give one-line errors") {
  TempDir dir;
  CHECK_THROWS_AS(read_volume(dir / "missing.nrrd"), Error);
  {
    std::ofstream(dir / "junk.nrrd") << "this is not a nrrd";
  }
  try {
    read_volume(dir / "junk.nrrd");
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find('\n') == std::string::npos);
  }
  {
    std::ofstream(dir / "short.nrrd") << "NRRD0004\ntype: float\ndimension: 3\nsizes: 4 4 4\nencoding: raw\nendian: little\n\nabc";
  }
  CHECK_THROWS_AS(read_volume(dir / "short.nrrd"), Error);
  {
    // 4 axes of unknown kind are a series (x, y, z, t) now; 6 axes are nothing we read.
    std::ofstream four(dir / "four.nrrd");
    four << "NRRD0004\ntype: uchar\ndimension: 4\nsizes: 3 2 2 2\nencoding: ascii\n\n";
    for (int i = 0; i < 24; ++i) four << "1 ";
    std::ofstream six(dir / "six.nrrd");
    six << "NRRD0004\ntype: uchar\ndimension: 6\nsizes: 3 2 2 2 2 2\nencoding: ascii\n\n";
    for (int i = 0; i < 96; ++i) six << "1 ";
  }
  CHECK(read_volume(dir / "four.nrrd").volume.size() == std::array<int, 4>{3, 2, 2, 2});
  try {
    read_volume(dir / "six.nrrd");
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("3x2x2x2x2x2") != std::string::npos);
    CHECK(std::string(e.what()).find('\n') == std::string::npos);
  }
  CHECK_THROWS_AS(write_volume(dir / "x.png", Volume(2, 2, 2), VolumeSampleType::uint8, VolumeEncoding::raw), Error);
}

TEST_CASE("read_volume: a 2-axis NRRD is one slice - a leading axis of size 1 is dropped") {
  TempDir dir;
  {
    std::ofstream(dir / "slice.nrrd") << "NRRD0004\ntype: float\ndimension: 2\nsizes: 3 2\nencoding: ascii\n\n1 2 3 4 5 6\n";
    std::ofstream(dir / "scalar4.nrrd")
        << "NRRD0004\ntype: short\ndimension: 4\nsizes: 1 2 1 2\nencoding: ascii\n\n-1 2 3 4\n";
  }
  const VolumeFile s = read_volume(dir / "slice.nrrd");
  CHECK(s.volume.nx == 3);
  CHECK(s.volume.ny == 2);
  CHECK(s.volume.nz == 1);
  CHECK(s.encoding == VolumeEncoding::ascii);
  // Enlarged along its thin axis too, it is written with 3 axes (as before series).
  write_volume(dir / "slice2.nrrd", Volume(6, 4, 2), s.type, VolumeEncoding::raw, s.header.get());
  CHECK(read_volume(dir / "slice2.nrrd").volume.size() == std::array<int, 4>{6, 4, 2, 1});
  const VolumeFile f = read_volume(dir / "scalar4.nrrd");
  CHECK(f.volume.nx == 2);
  CHECK(f.volume.nz == 2);
  CHECK(f.volume.voxels == std::vector<float>{-1, 2, 3, 4});
  // Written back with the same layout.
  write_volume(dir / "scalar4b.nrrd", f.volume, f.type, VolumeEncoding::raw, f.header.get());
  Nrrd* n = nrrdNew();
  REQUIRE(nrrdLoad(n, (dir / "scalar4b.nrrd").c_str(), nullptr) == 0);
  CHECK(n->dim == 4);
  nrrdNuke(n);
}

TEST_CASE("check_volume_output_path: refuses the input, other extensions and missing directories") {
  TempDir dir;
  write_volume(dir / "a.nrrd", Volume(2, 2, 2), VolumeSampleType::uint8, VolumeEncoding::raw);
  CHECK_THROWS_AS(check_volume_output_path(dir / "a.nrrd", dir / "a.nrrd"), Error);
  CHECK_THROWS_AS(check_volume_output_path(dir / "b.png", dir / "a.nrrd"), Error);
  CHECK_THROWS_AS(check_volume_output_path(dir / "nodir/b.nrrd", dir / "a.nrrd"), Error);
  CHECK_NOTHROW(check_volume_output_path(dir / "b.nhdr", dir / "a.nrrd"));
  CHECK(is_volume_path("X.NRRD"));
  CHECK_FALSE(is_volume_path("x.png"));
  CHECK(parse_sample_type("ushort") == VolumeSampleType::uint16);
  CHECK_THROWS_AS(parse_sample_type("rgb"), Error);
  CHECK_THROWS_AS(parse_encoding("zip"), Error);
}

TEST_CASE("read_volume / write_volume: a leading RGB-color axis is the channels - kinds and geometry are kept") {
  TempDir dir;
  const std::size_t C = 3, nx = 4, ny = 5, nz = 6;
  std::vector<float> data(C * nx * ny * nz);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<float>(i % 97) / 4;
  {
    Nrrd* n = nrrdNew();
    REQUIRE(nrrdWrap_va(n, data.data(), nrrdTypeFloat, 4, C, nx, ny, nz) == 0);
    n->space = nrrdSpaceRightAnteriorSuperior;
    n->spaceDim = 3;
    n->axis[0].kind = nrrdKindRGBColor;
    for (int d = 0; d < 3; ++d) n->axis[0].spaceDirection[d] = AIR_NAN;
    for (int a = 1; a < 4; ++a) {
      n->axis[a].kind = nrrdKindSpace;
      for (int d = 0; d < 3; ++d) n->axis[a].spaceDirection[d] = a - 1 == d ? 0.5 * a : 0.0;
    }
    n->spaceOrigin[0] = 10, n->spaceOrigin[1] = -5, n->spaceOrigin[2] = 1;
    REQUIRE(nrrdSave((dir / "rgb.nrrd").c_str(), n, nullptr) == 0);
    nrrdNix(n);  // the data stays ours
  }
  const VolumeFile in = read_volume(dir / "rgb.nrrd");
  REQUIRE(in.volume.channels == 3);
  CHECK(in.volume.nx == 4);
  CHECK(in.volume.ny == 5);
  CHECK(in.volume.nz == 6);
  CHECK(in.volume.voxels == data);
  CHECK(in.volume.at(1, 2, 3, 2) == data[((3 * ny + 2) * nx + 1) * C + 2]);

  Volume big(8, 10, 6, 3, 0.0f);
  for (std::size_t i = 0; i < big.voxels.size(); ++i) big.voxels[i] = static_cast<float>(i % 13);
  write_volume(dir / "big.nrrd", big, in.type, VolumeEncoding::gzip, in.header.get());
  Nrrd* n = nrrdNew();
  REQUIRE(nrrdLoad(n, (dir / "big.nrrd").c_str(), nullptr) == 0);
  CHECK(n->dim == 4);
  CHECK(n->axis[0].size == 3);
  CHECK(n->axis[0].kind == nrrdKindRGBColor);
  CHECK(n->axis[1].kind == nrrdKindSpace);
  CHECK(n->axis[1].spaceDirection[0] == doctest::Approx(0.25));  // x2
  CHECK(n->axis[3].spaceDirection[2] == doctest::Approx(1.5));    // x1
  CHECK(n->spaceOrigin[0] == doctest::Approx(10 - 0.25 * 0.5));
  CHECK(n->spaceOrigin[2] == doctest::Approx(1.0));
  nrrdNuke(n);
  const VolumeFile back = read_volume(dir / "big.nrrd");
  CHECK(back.volume.channels == 3);
  CHECK(back.volume.voxels == big.voxels);
  CHECK_THROWS_AS(write_volume(dir / "one.nrrd", Volume(8, 10, 6), in.type, VolumeEncoding::raw, in.header.get()),
                  Error);  // another number of channels than the input's
}

TEST_CASE("read_volume / write_volume: a 3-vector slice, and channels written without an input header") {
  TempDir dir;
  {
    std::ofstream(dir / "vec.nrrd") << "NRRD0004\ntype: float\ndimension: 3\nsizes: 3 2 2\nkinds: 3-vector domain "
                                       "domain\nencoding: ascii\n\n1 2 3 4 5 6 7 8 9 10 11 12\n";
  }
  const VolumeFile v = read_volume(dir / "vec.nrrd");
  CHECK(v.volume.channels == 3);
  CHECK(v.volume.nx == 2);
  CHECK(v.volume.ny == 2);
  CHECK(v.volume.nz == 1);
  CHECK(v.volume.at(1, 1, 0, 2) == 12);
  write_volume(dir / "vec2.nrrd", v.volume, v.type, VolumeEncoding::raw, v.header.get());
  Nrrd* n = nrrdNew();
  REQUIRE(nrrdLoad(n, (dir / "vec2.nrrd").c_str(), nullptr) == 0);
  CHECK(n->dim == 3);
  CHECK(n->axis[0].kind == nrrdKind3Vector);
  nrrdNuke(n);

  Volume two(3, 2, 2, 2, 0.5f);
  write_volume(dir / "two.nhdr", two, VolumeSampleType::float32, VolumeEncoding::raw);
  n = nrrdNew();
  REQUIRE(nrrdLoad(n, (dir / "two.nhdr").c_str(), nullptr) == 0);
  CHECK(n->dim == 4);
  CHECK(n->axis[0].kind == nrrdKindVector);
  nrrdNuke(n);
  const VolumeFile back = read_volume(dir / "two.nhdr");
  CHECK(back.volume.channels == 2);
  CHECK(back.volume.voxels == two.voxels);
}

namespace {

// A 4-axis series (x, y, z, t) written by Teem directly: world geometry on
// the spatial axes, a time axis of kind time with spacing and centring
// given (center: nrrdCenterNode, nrrdCenterCell or nrrdCenterUnknown).
void write_series_nrrd(const std::string& path, const Volume& v, int center) {
  Nrrd* n = nrrdNew();
  std::vector<float> data = v.voxels;
  REQUIRE(nrrdWrap_va(n, data.data(), nrrdTypeFloat, 4, std::size_t(v.nx), std::size_t(v.ny), std::size_t(v.nz),
                      std::size_t(v.nt)) == 0);
  n->space = nrrdSpaceRightAnteriorSuperior;
  n->spaceDim = 3;
  const double dirs[3][3] = {{0.5, 0, 0}, {0, 0.6, 0}, {0, 0, 2.0}};
  for (int a = 0; a < 3; ++a) {
    for (int d = 0; d < 3; ++d) n->axis[a].spaceDirection[d] = dirs[a][d];
    n->axis[a].center = nrrdCenterCell;
    n->axis[a].kind = nrrdKindSpace;
  }
  n->axis[3].kind = nrrdKindTime;
  n->axis[3].center = center;
  n->axis[3].spacing = 0.5;
  n->spaceOrigin[0] = 10, n->spaceOrigin[1] = -5, n->spaceOrigin[2] = 1;
  REQUIRE(nrrdSave(path.c_str(), n, nullptr) == 0);
  nrrdNix(n);
}

Volume ramp4(const std::array<int, 4>& size, int channels = 1) {
  Volume v(size, channels, 0.0f);
  for (std::size_t i = 0; i < v.voxels.size(); ++i) v.voxels[i] = static_cast<float>(0.001 * double(i) + 0.25);
  return v;
}

}  // namespace

TEST_CASE("read_volume / write_volume: a 4-axis series round-trips, time node-centred with spacing / s, space as in 3D") {
  TempDir dir;
  const Volume v = ramp4({4, 5, 3, 6});
  write_series_nrrd(dir / "series.nrrd", v, nrrdCenterNode);
  const VolumeFile in = read_volume(dir / "series.nrrd");
  CHECK(in.volume.size() == std::array<int, 4>{4, 5, 3, 6});
  CHECK(in.volume.channels == 1);
  CHECK(in.volume.voxels == v.voxels);
  CHECK(in.node_centred == std::array<bool, 4>{false, false, false, true});
  // x2 in space, x4 in time: 6 steps -> 21.
  const Volume big({8, 10, 6, 21}, 1, 0.5f);
  write_volume(dir / "big.nrrd", big, in.type, in.encoding, in.header.get(), "test", in.node_centred);
  Nrrd* n = nrrdNew();
  REQUIRE(nrrdLoad(n, (dir / "big.nrrd").c_str(), nullptr) == 0);
  REQUIRE(n->dim == 4);
  CHECK(n->axis[3].size == 21);
  CHECK(n->axis[3].kind == nrrdKindTime);
  CHECK(n->axis[3].center == nrrdCenterNode);
  CHECK(n->axis[3].spacing == doctest::Approx(0.125));  // 0.5 / 4: the same first and last instants
  CHECK(n->axis[0].spaceDirection[0] == doctest::Approx(0.25));
  CHECK(n->axis[2].spaceDirection[2] == doctest::Approx(1.0));
  CHECK(n->axis[0].center == nrrdCenterCell);
  CHECK(n->spaceOrigin[0] == doctest::Approx(10 - 0.25 * 0.5));  // cells: the first sample at index -0.25
  CHECK(n->spaceOrigin[2] == doctest::Approx(1 - 0.25 * 2.0));
  nrrdNuke(n);
  const VolumeFile back = read_volume(dir / "big.nrrd");
  CHECK(back.volume.size() == std::array<int, 4>{8, 10, 6, 21});
  CHECK(back.node_centred[3]);
}

TEST_CASE("read_volume: a time axis said to be cells is cell-centred, unknown centring is node (instants)") {
  TempDir dir;
  const Volume v = ramp4({3, 3, 3, 4});
  write_series_nrrd(dir / "cells.nrrd", v, nrrdCenterCell);
  write_series_nrrd(dir / "unknown.nrrd", v, nrrdCenterUnknown);
  CHECK_FALSE(read_volume(dir / "cells.nrrd").node_centred[3]);
  CHECK(read_volume(dir / "unknown.nrrd").node_centred[3]);
  // Written cell-centred, the time axis scales as the space does.
  const VolumeFile in = read_volume(dir / "cells.nrrd");
  write_volume(dir / "big.nrrd", Volume({3, 3, 3, 8}, 1, 0.0f), in.type, in.encoding, in.header.get(), {},
               in.node_centred);
  Nrrd* n = nrrdNew();
  REQUIRE(nrrdLoad(n, (dir / "big.nrrd").c_str(), nullptr) == 0);
  CHECK(n->axis[3].center == nrrdCenterCell);
  CHECK(n->axis[3].spacing == doctest::Approx(0.25));
  nrrdNuke(n);
}

TEST_CASE("read_volume / write_volume: series without a header, scalar and with channels (5 axes)") {
  TempDir dir;
  const Volume scalar = ramp4({5, 4, 3, 7});
  write_volume(dir / "s.nrrd", scalar, VolumeSampleType::float32, VolumeEncoding::gzip);
  const VolumeFile s = read_volume(dir / "s.nrrd");
  CHECK(s.volume.size() == scalar.size());
  CHECK(s.volume.voxels == scalar.voxels);
  CHECK(s.node_centred[3]);
  const Volume rgb = ramp4({3, 4, 2, 5}, 3);
  write_volume(dir / "c.nhdr", rgb, VolumeSampleType::float32, VolumeEncoding::raw);
  const VolumeFile c = read_volume(dir / "c.nhdr");
  CHECK(c.volume.channels == 3);
  CHECK(c.volume.size() == rgb.size());
  CHECK(c.volume.voxels == rgb.voxels);
  // The sizes limit counts every time step.
  VolumeReadOptions small;
  small.max_voxels = 5 * 4 * 3 * 7 - 1;
  CHECK_THROWS_WITH_AS(read_volume(dir / "s.nrrd", small), doctest::Contains("5x4x3x7"), Error);
}
