#include "eval/volume_fields.hpp"

#include "util/error.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

namespace ddt {
namespace {

double sphere(double x, double y, double z) {
  const double dx = x - 0.5, dy = y - 0.5, dz = z - 0.5;
  return dx * dx + dy * dy + dz * dz < 0.35 * 0.35 ? 1.0 : 0.0;
}

double hydrogen(double x, double y, double z) {
  constexpr double half_width = 20.0;  // Bohr radii from the centre to a face
  const double px = (2 * x - 1) * half_width, py = (2 * y - 1) * half_width, pz = (2 * z - 1) * half_width;
  const double r2 = px * px + py * py + pz * pz;
  const double r = std::sqrt(r2);
  // r^2 (3 cos^2 - 1) = 3 z^2 - r^2; squared: r^4 (3 cos^2 - 1)^2.
  const double angular = 3 * pz * pz - r2;
  // Maximum on the z axis at r = 6: (2 * 36)^2 exp(-4).
  static const double peak = (2.0 * 36.0) * (2.0 * 36.0) * std::exp(-4.0);
  return angular * angular * std::exp(-2.0 * r / 3.0) / peak;
}

// The moving sphere at time t: the squared distance of (x, y, z) from its
// centre, and its radius.
struct MovingBall {
  double distance2, radius;
};
MovingBall moving_ball(double x, double y, double z, double t) {
  const double dx = x - (0.3 + 0.4 * t), dy = y - (0.45 + 0.1 * t), dz = z - 0.5;
  return {dx * dx + dy * dy + dz * dz, 0.15 + 0.1 * t};
}

double moving_sphere_distance(double x, double y, double z, double t) {
  const MovingBall b = moving_ball(x, y, z, t);
  return std::sqrt(b.distance2) - b.radius;
}

double moving_sphere(double x, double y, double z, double t) {
  const MovingBall b = moving_ball(x, y, z, t);
  return b.distance2 < b.radius * b.radius ? 1.0 : 0.0;
}

}  // namespace

const std::vector<VolumeSeriesField>& volume_series_fields() {
  static const std::vector<VolumeSeriesField> fields = {
      {"moving-sphere",
       "solid ball, centre (0.3, 0.45, 0.5) -> (0.7, 0.55, 0.5), radius 0.15 -> 0.25 as t goes 0 -> 1; 1 inside",
       &moving_sphere, 0.5, &moving_sphere_distance},
  };
  return fields;
}

const VolumeSeriesField& find_volume_series_field(const std::string& name) {
  for (const auto& f : volume_series_fields())
    if (f.name == name) return f;
  throw Error("unknown series field '" + name + "' (valid: moving-sphere)");
}

Volume sample_series_field(const VolumeSeriesField& field, const std::array<int, 4>& size, int ss) {
  for (int n : size)
    if (n < 1) throw Error("sample_series_field: sizes must be >= 1");
  if (ss < 1) throw Error("sample_series_field: supersampling must be >= 1");
  const int nx = size[0], ny = size[1], nz = size[2], nt = size[3];  // not a structured binding: clang 14 cannot capture those
  Volume v(size, 1, 0.0f);
  const double inv = 1.0 / (double(ss) * ss * ss);
  tbb::parallel_for(0, nz * nt, [&](int kl) {
    const int k = kl % nz, l = kl / nz;
    const double t = nt > 1 ? double(l) / (nt - 1) : 0.0;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        double sum = 0;
        for (int c = 0; c < ss; ++c)
          for (int b = 0; b < ss; ++b)
            for (int a = 0; a < ss; ++a)
              sum += field.value((i + (a + 0.5) / ss) / nx, (j + (b + 0.5) / ss) / ny, (k + (c + 0.5) / ss) / nz, t);
        v.at4(i, j, k, l) = static_cast<float>(sum * inv);
      }
  });
  return v;
}

const std::vector<VolumeField>& volume_fields() {
  static const std::vector<VolumeField> fields = {
      {"sphere", "solid ball of radius 0.35 centred in the cube, 1 inside, 0 outside", &sphere, 0.5},
      {"hydrogen", "hydrogen 3d_z2 orbital density r^4 exp(-2r/3) (3cos^2 - 1)^2 over [-20, 20]^3 a0, max 1",
       &hydrogen, 0.1},
  };
  return fields;
}

const VolumeField& find_volume_field(const std::string& name) {
  for (const auto& f : volume_fields())
    if (f.name == name) return f;
  throw Error("unknown field '" + name + "' (valid: sphere, hydrogen; series: moving-sphere)");
}

Volume sample_field(const VolumeField& field, int nx, int ny, int nz, int ss) {
  if (nx < 1 || ny < 1 || nz < 1 || ss < 1) throw Error("sample_field: sizes and supersampling must be >= 1");
  Volume v(nx, ny, nz);
  const double inv = 1.0 / (double(ss) * ss * ss);
  tbb::parallel_for(0, nz, [&](int k) {
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        double sum = 0;
        for (int c = 0; c < ss; ++c)
          for (int b = 0; b < ss; ++b)
            for (int a = 0; a < ss; ++a)
              sum += field.value((i + (a + 0.5) / ss) / nx, (j + (b + 0.5) / ss) / ny, (k + (c + 0.5) / ss) / nz);
        v.at(i, j, k) = static_cast<float>(sum * inv);
      }
  });
  return v;
}

double volume_rmse(const Volume& a, const Volume& b) {
  if (a.size() != b.size() || a.channels != b.channels) throw Error("volume_rmse: the volumes differ in size");
  if (a.empty()) throw Error("volume_rmse: the volumes are empty");
  double sum = 0;
  for (std::size_t i = 0; i < a.voxels.size(); ++i) {
    const double d = double(a.voxels[i]) - b.voxels[i];
    sum += d * d;
  }
  return std::sqrt(sum / a.voxels.size());
}

double volume_psnr(const Volume& a, const Volume& b, double peak) {
  const double e = volume_rmse(a, b);
  return e == 0 ? std::numeric_limits<double>::infinity() : 20.0 * std::log10(peak / e);
}

}  // namespace ddt
