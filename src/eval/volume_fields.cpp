#include "eval/volume_fields.hpp"

#include "util/error.hpp"
#include "util/text.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
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

// Signed distance to the box of half-extents h about the origin.
double box_distance(double x, double y, double z, const double h[3]) {
  const double qx = std::abs(x) - h[0], qy = std::abs(y) - h[1], qz = std::abs(z) - h[2];
  const double ox = std::max(qx, 0.0), oy = std::max(qy, 0.0), oz = std::max(qz, 0.0);
  return std::sqrt(ox * ox + oy * oy + oz * oz) + std::min(std::max({qx, qy, qz}), 0.0);
}

// A box translating along a diagonal: planar faces, edges and corners
// moving across every axis of the grid at once.
double moving_box_distance(double x, double y, double z, double t) {
  static const double h[3] = {0.16, 0.12, 0.14};
  return box_distance(x - (0.3 + 0.35 * t), y - (0.35 + 0.25 * t), z - (0.4 + 0.15 * t), h);
}
double moving_box(double x, double y, double z, double t) { return moving_box_distance(x, y, z, t) < 0 ? 1.0 : 0.0; }

// A long bar turning about the z axis through the cube's centre: every
// point of its surface moves at its own speed and direction.
double spinning_bar_distance(double x, double y, double z, double t) {
  static const double h[3] = {0.32, 0.07, 0.2};
  const double angle = 1.0 * t;  // radians over the series
  const double c = std::cos(angle), s = std::sin(angle);
  const double dx = x - 0.5, dy = y - 0.5;
  return box_distance(c * dx + s * dy, -s * dx + c * dy, z - 0.5, h);
}
double spinning_bar(double x, double y, double z, double t) {
  return spinning_bar_distance(x, y, z, t) < 0 ? 1.0 : 0.0;
}

// A smooth Gaussian blob (sigma 0.1, peak 1) moving along a diagonal: no
// edge at all, where the separable cubic kernels are at their best.
constexpr double blob_sigma = 0.1;
double blob_r2(double x, double y, double z, double t) {
  const double dx = x - (0.35 + 0.3 * t), dy = y - (0.4 + 0.2 * t), dz = z - (0.45 + 0.1 * t);
  return dx * dx + dy * dy + dz * dz;
}
double moving_blob(double x, double y, double z, double t) {
  return std::exp(-blob_r2(x, y, z, t) / (2 * blob_sigma * blob_sigma));
}
// The level 0.5 is the sphere r = sigma sqrt(2 ln 2).
double moving_blob_distance(double x, double y, double z, double t) {
  return std::sqrt(blob_r2(x, y, z, t)) - blob_sigma * std::sqrt(2 * std::log(2.0));
}

}  // namespace

const std::vector<VolumeSeriesField>& volume_series_fields() {
  static const std::vector<VolumeSeriesField> fields = {
      {"moving-sphere",
       "solid ball, centre (0.3, 0.45, 0.5) -> (0.7, 0.55, 0.5), radius 0.15 -> 0.25 as t goes 0 -> 1; 1 inside",
       &moving_sphere, 0.5, &moving_sphere_distance},
      {"moving-box",
       "solid box, half-extents (0.16, 0.12, 0.14), centre (0.3, 0.35, 0.4) -> (0.65, 0.6, 0.55) as t goes 0 -> 1; "
       "1 inside",
       &moving_box, 0.5, &moving_box_distance},
      {"spinning-bar",
       "solid bar, half-extents (0.32, 0.07, 0.2), centred, turning 1 radian about z as t goes 0 -> 1; 1 inside",
       &spinning_bar, 0.5, &spinning_bar_distance},
      {"moving-blob",
       "Gaussian blob, sigma 0.1, peak 1, centre (0.35, 0.4, 0.45) -> (0.65, 0.6, 0.55) as t goes 0 -> 1",
       &moving_blob, 0.5, &moving_blob_distance},
  };
  return fields;
}

const VolumeSeriesField& find_volume_series_field(const std::string& name) {
  for (const auto& f : volume_series_fields())
    if (f.name == name) return f;
  throw Error("unknown series field '" + name + "' (valid: " + volume_series_field_names() + ")");
}

std::string volume_series_field_names() {
  std::vector<std::string> names;
  for (const auto& f : volume_series_fields()) names.push_back(f.name);
  return joined(names);
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

std::string volume_field_names() {
  std::vector<std::string> names;
  for (const auto& f : volume_fields()) names.push_back(f.name);
  return joined(names);
}

const VolumeField& find_volume_field(const std::string& name) {
  for (const auto& f : volume_fields())
    if (f.name == name) return f;
  throw Error("unknown field '" + name + "' (valid: " + volume_field_names() + "; series: " +
              volume_series_field_names() + ")");
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
