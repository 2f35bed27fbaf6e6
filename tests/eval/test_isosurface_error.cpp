// Tests for isosurface_error.hpp: crossings of a linear ramp land exactly
// on its plane, a known shift is measured as itself, the sphere's count of
// true crossings, and the step filter.

#include "eval/isosurface_error.hpp"

#include "eval/volume_fields.hpp"
#include "util/error.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace ddt;

namespace {

// v = 0.5 + slope * (x - plane) at the voxel centres, x in unit-cube units.
Volume ramp(const std::array<int, 4>& size, double plane, double slope) {
  Volume v(size, 1, 0.0f);
  for (int t = 0; t < size[3]; ++t)
    for (int z = 0; z < size[2]; ++z)
      for (int y = 0; y < size[1]; ++y)
        for (int x = 0; x < size[0]; ++x)
          v.at4(x, y, z, t) = static_cast<float>(0.5 + slope * ((x + 0.5) / size[0] - plane));
  return v;
}

}  // namespace

TEST_CASE("isosurface_error: a linear ramp's crossings lie on its plane - a shift is measured as itself") {
  const std::array<int, 4> size{16, 8, 6, 3};
  const double plane = 0.4;  // between voxel centres 6 and 7
  const Volume v = ramp(size, plane, 2.0);
  const auto on_plane = [&](double x, double, double, double) { return x - plane; };
  const IsosurfaceError exact = isosurface_error(v, 0.5, on_plane);
  CHECK(exact.crossings == 8 * 6 * 3);  // one per x line
  CHECK(exact.true_crossings == exact.crossings);
  CHECK(exact.max < 1e-5);

  const double shift = 0.25 / size[0];  // a quarter voxel
  const auto shifted = [&](double x, double, double, double) { return x - (plane + shift); };
  const IsosurfaceError off = isosurface_error(v, 0.5, shifted);
  CHECK(off.rms == doctest::Approx(0.25).epsilon(1e-4));
  CHECK(off.mean == doctest::Approx(0.25).epsilon(1e-4));
  CHECK(off.max == doctest::Approx(0.25).epsilon(1e-4));

  const IsosurfaceError one_step = isosurface_error(v, 0.5, on_plane, [](int l) { return l == 1; });
  CHECK(one_step.crossings == 8 * 6);
}

TEST_CASE("isosurface_error: the shading normal is exact on a ramp, tilted by quantization's terraces") {
  // Values rise along x: inside (above the level) is x > plane, where the
  // distance plane - x is negative; the picture's normal points to -x.
  const std::array<int, 4> size{16, 8, 6, 2};
  const double plane = 0.4;
  const Volume v = ramp(size, plane, 2.0);
  const IsosurfaceError along_x =
      isosurface_error(v, 0.5, [&](double x, double, double, double) { return plane - x; });
  CHECK(along_x.crossings == 8 * 6 * 2);
  CHECK(along_x.normal_rms < 1e-6);
  // With the distance's sign turned, the normal points the other way.
  const IsosurfaceError turned = isosurface_error(v, 0.5, [&](double x, double, double, double) { return x - plane; });
  CHECK(turned.normal_rms == doctest::Approx(180).epsilon(1e-6));

  // A plane tilted in x-y, smooth and quantized to 6 levels: the terraces
  // of the quantized one tilt its shading; where they do not reach (the
  // smooth one) only the borders' clamped differences do.
  const int n = 32;
  const double a = std::cos(0.5), b = std::sin(0.5);
  const auto distance = [&](double x, double y, double, double) { return 0.5 - (a * x + b * y); };
  Volume smooth({n, n, 4, 1}, 1, 0.0f), terraced({n, n, 4, 1}, 1, 0.0f);
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double value = 0.5 - 1.5 * distance((x + 0.5) / n, (y + 0.5) / n, 0, 0);
        smooth.at4(x, y, z, 0) = static_cast<float>(value);
        terraced.at4(x, y, z, 0) = static_cast<float>(std::round(value * 5) / 5);
      }
  const IsosurfaceError fine = isosurface_error(smooth, 0.5, distance);
  const IsosurfaceError steps = isosurface_error(terraced, 0.5, distance);
  MESSAGE("tilted plane: normal RMS " << fine.normal_rms << " degrees smooth, " << steps.normal_rms << " terraced");
  CHECK(fine.normal_p99 < 20);  // the border lines: a half step clamped
  CHECK(steps.normal_rms > 3 * fine.normal_rms);
}

TEST_CASE("isosurface_error: the moving sphere sampled finely has its surface within a voxel, everywhere") {
  const VolumeSeriesField& field = find_volume_series_field("moving-sphere");
  REQUIRE(field.surface_distance);
  const Volume v = sample_series_field(field, {32, 32, 32, 3}, 4);
  const IsosurfaceError e = isosurface_error(v, field.iso_level, field.surface_distance);
  MESSAGE("moving sphere 32^3 x 3, box-filtered: isosurface RMS " << e.rms << " voxel, max " << e.max);
  CHECK(e.true_crossings > 1000);
  // Every line through the ball crosses its surface twice: the box filter
  // keeps the count but for lines grazing it.
  CHECK(std::abs(e.crossings - e.true_crossings) < e.true_crossings / 20);
  CHECK(e.max < 1.0);
  CHECK(e.rms < 0.3);
  MESSAGE("shading normal RMS " << e.normal_rms << " degrees, p99 " << e.normal_p99);
  CHECK(e.normal_rms < 15);  // degrees: a ball 6 voxels across, shaded from half-voxel differences
  // An empty field has no surface, and the count says it was lost.
  const Volume empty(std::array<int, 4>{32, 32, 32, 3}, 1, 0.0f);
  const IsosurfaceError lost = isosurface_error(empty, field.iso_level, field.surface_distance);
  CHECK(lost.crossings == 0);
  CHECK(lost.true_crossings == e.true_crossings);
  CHECK_THROWS_AS(isosurface_error(v, 0.5, nullptr), Error);
}

TEST_CASE("series fields: each surface distance is the field's own level set, and finely sampled within a voxel") {
  for (const VolumeSeriesField& field : volume_series_fields()) {
    CAPTURE(field.name);
    REQUIRE(field.surface_distance);
    // The distance's sign is the side of the level: inside (value above
    // it) negative, at points spread over the cube and the series.
    int inside = 0, outside = 0;
    for (int i = 0; i < 4000; ++i) {
      const double x = ((i * 37) % 101 + 0.5) / 101, y = ((i * 53) % 97 + 0.5) / 97, z = ((i * 71) % 89 + 0.5) / 89,
                   t = (i % 7) / 6.0;
      const double d = field.surface_distance(x, y, z, t), v = field.value(x, y, z, t);
      if (std::abs(d) < 1e-9) continue;
      CHECK((d < 0) == (v > field.iso_level));
      (d < 0 ? inside : outside) += 1;
    }
    CHECK(inside > 20);
    CHECK(outside > 20);
    const Volume v = sample_series_field(field, {32, 32, 32, 3}, 4);
    const IsosurfaceError e = isosurface_error(v, field.iso_level, field.surface_distance);
    MESSAGE(field.name << " 32^3 x 3, box-filtered: isosurface RMS " << e.rms << " voxel, max " << e.max);
    // Lines grazing a flat face (the thin bar's) cross it or not by a hair.
    CHECK(e.true_crossings > 500);
    CHECK(std::abs(e.crossings - e.true_crossings) < e.true_crossings / 5);
    CHECK(e.max < 1.0);
    CHECK(e.rms < 0.3);
  }
  CHECK(volume_series_fields().size() >= 4);
}
