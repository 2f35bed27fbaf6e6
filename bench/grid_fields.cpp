// grid_fields — analytic test fields for the scattered-data comparison
// (scripts/compare_gdal.sh): scattered samples to CSV, and the error of a
// gridded result against the true field.
//
//   grid_fields points FIELD N SEED out.csv [E]  N uniform random points in
//                                             [0,E]^2 (default E = 1) plus the
//                                             4 corners, "x,y,z"
//   grid_fields rmse FIELD image              RMSE and max error of channel 0
//                                             against FIELD at the pixel centres
//   grid_fields truth FIELD W H out.exr       FIELD at the pixel centres (float)
//
// Fields on the unit square, stretched to [0,E]^2 (f(x / E, y / E)):
//   fault   a plane 0.3 x + 0.2 y with a unit step across the line
//           y = 0.3 + 0.6 x (a normal fault seen from above)
//   ridge   a tent-shaped ridge, max(0, 1 - d / 0.2), d the distance to the
//           line 0.8 x + 0.6 y = 0.7: a sharp crest and two sharp feet
//   smooth  Franke's function (R. Franke, 1979), the standard smooth test
//           function for scattered-data interpolation
// Pixel centres follow ddtscale grid and gdal_grid over bounds [0,E]^2:
// pixel (i, j) samples E ((i + 0.5) / W, 1 - (j + 0.5) / H), row 0 at the top.
// Pixels that are NaN (no-data) are counted, not scored.
//
// Standalone (only OpenImageIO): the script compiles it with
//   g++ -O2 -std=c++20 bench/grid_fields.cpp -lOpenImageIO -lOpenImageIO_Util

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

double fault(double x, double y) { return 0.3 * x + 0.2 * y + (y > 0.3 + 0.6 * x ? 1.0 : 0.0); }

double ridge(double x, double y) { return std::max(0.0, 1.0 - std::abs(0.8 * x + 0.6 * y - 0.7) / 0.2); }

double franke(double x, double y) {
  const double a = 9 * x, b = 9 * y;
  return 0.75 * std::exp(-((a - 2) * (a - 2) + (b - 2) * (b - 2)) / 4) +
         0.75 * std::exp(-(a + 1) * (a + 1) / 49 - (b + 1) / 10) +
         0.5 * std::exp(-((a - 7) * (a - 7) + (b - 3) * (b - 3)) / 4) -
         0.2 * std::exp(-(a - 4) * (a - 4) - (b - 7) * (b - 7));
}

using Field = double (*)(double, double);

Field field_named(const std::string& name) {
  if (name == "fault") return fault;
  if (name == "ridge") return ridge;
  if (name == "smooth") return franke;
  std::fprintf(stderr, "grid_fields: unknown field '%s' (fault, ridge, smooth)\n", name.c_str());
  std::exit(2);
}

// Uniform in [0, 1) from the raw 64-bit engine, the same on every platform.
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

int write_points(Field f, long n, unsigned long seed, const char* path, double extent) {
  std::FILE* out = std::fopen(path, "w");
  if (!out) {
    std::fprintf(stderr, "grid_fields: cannot write '%s'\n", path);
    return 1;
  }
  std::fprintf(out, "x,y,z\n");
  const double corners[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  for (const auto& c : corners)
    std::fprintf(out, "%.17g,%.17g,%.17g\n", c[0] * extent, c[1] * extent, f(c[0], c[1]));
  std::mt19937_64 rng(seed);
  for (long i = 0; i < n; ++i) {
    const double x = unit(rng), y = unit(rng);
    std::fprintf(out, "%.17g,%.17g,%.17g\n", x * extent, y * extent, f(x, y));
  }
  return std::fclose(out) == 0 ? 0 : 1;
}

int score(Field f, const char* path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::fprintf(stderr, "grid_fields: cannot read '%s'\n", path);
    return 1;
  }
  const OIIO::ImageSpec spec = in->spec();
  const int W = spec.width, H = spec.height, C = spec.nchannels;
  std::vector<float> px(static_cast<std::size_t>(W) * H * C);
  if (!in->read_image(0, 0, 0, C, OIIO::TypeDesc::FLOAT, px.data())) {
    std::fprintf(stderr, "grid_fields: cannot read '%s'\n", path);
    return 1;
  }
  double sum = 0, worst = 0;
  long scored = 0, nodata = 0;
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      const float v = px[(static_cast<std::size_t>(j) * W + i) * C];
      if (!std::isfinite(v)) {
        ++nodata;
        continue;
      }
      const double d = v - f((i + 0.5) / W, 1.0 - (j + 0.5) / H);
      sum += d * d;
      worst = std::max(worst, std::abs(d));
      ++scored;
    }
  std::printf("rmse %.5g max %.4g scored %ld nodata %ld\n", scored ? std::sqrt(sum / scored) : 0.0, worst, scored,
              nodata);
  return 0;
}

int write_truth(Field f, int W, int H, const char* path) {
  std::vector<float> px(static_cast<std::size_t>(W) * H);
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) px[static_cast<std::size_t>(j) * W + i] = static_cast<float>(f((i + 0.5) / W, 1.0 - (j + 0.5) / H));
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->open(path, OIIO::ImageSpec(W, H, 1, OIIO::TypeDesc::FLOAT)) ||
      !out->write_image(OIIO::TypeDesc::FLOAT, px.data()) || !out->close()) {
    std::fprintf(stderr, "grid_fields: cannot write '%s'\n", path);
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string cmd = argc > 1 ? argv[1] : "";
  if (cmd == "points" && (argc == 6 || argc == 7))
    return write_points(field_named(argv[2]), std::atol(argv[3]), std::strtoul(argv[4], nullptr, 10), argv[5],
                        argc == 7 ? std::atof(argv[6]) : 1.0);
  if (cmd == "rmse" && argc == 4) return score(field_named(argv[2]), argv[3]);
  if (cmd == "truth" && argc == 6 && std::atoi(argv[3]) > 0 && std::atoi(argv[4]) > 0)
    return write_truth(field_named(argv[2]), std::atoi(argv[3]), std::atoi(argv[4]), argv[5]);
  std::fprintf(stderr,
               "usage: grid_fields points FIELD N SEED out.csv [EXTENT] | grid_fields rmse FIELD image |\n"
               "       grid_fields truth FIELD W H out.exr\n"
               "fields: fault, ridge, smooth\n");
  return 2;
}
