#include "image/image_mesh.hpp"

#include "util/error.hpp"
#include "image/optimizer_choice.hpp"
#include "image/triangulation.hpp"

#include <chrono>

namespace ddt {

DriveChannels drive_channels(const Image& src, const UpscaleOptions& options) {
  DriveChannels d;
  for (int c = 0; c < src.channels; ++c)
    if (c != options.alpha_channel) d.colour.push_back(c);
  if (options.luma_cost && d.colour.size() >= 3) {
    d.luma = true;
    d.K = 1;
    return d;
  }
  if (d.colour.size() > static_cast<std::size_t>(max_cost_channels))
    throw Error("the cost takes at most " + std::to_string(max_cost_channels) + " channels; this image has " +
                std::to_string(d.colour.size()) + " (use --cost-channel luma)");
  if (d.colour.empty()) d.colour.push_back(0);  // alpha alone: let it drive
  d.K = static_cast<int>(d.colour.size());
  d.identity = d.K == src.channels;
  return d;
}

std::vector<float> drive_values(const float* pixels, std::size_t n, int C, const DriveChannels& d) {
  std::vector<float> out(n * d.K);
  const std::vector<int>& colour = d.colour;
  if (d.luma) {
    // Rec. 601 weights, as the evaluation's Y.
    for (std::size_t i = 0; i < n; ++i) {
      const float* px = pixels + i * C;
      out[i] = 0.299f * px[colour[0]] + 0.587f * px[colour[1]] + 0.114f * px[colour[2]];
    }
    return out;
  }
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < d.K; ++k) out[i * d.K + k] = pixels[i * C + colour[k]];
  return out;
}

int optimizer_region_rows(int width, int height, const UpscaleOptions& options) {
  if (width < 2 || height < 2 || options.region_rows < 0) return 0;
  if (options.region_rows > 0) return options.region_rows;
  const long long cells_row = 2LL * (width - 1);
  const long long triangles = cells_row * (height - 1);
  if (triangles <= 2 * default_region_triangles) return 0;
  return static_cast<int>(image_region_triangles(width) / cells_row);
}

std::vector<Point2> pixel_centres(int width, int height) {
  std::vector<Point2> points(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) points[static_cast<std::size_t>(y) * width + x] = {x + 0.5, y + 0.5};
  return points;
}

Mesh2 image_mesh(const Image& src, const UpscaleOptions& options, UpscaleStats* stats) {
  if (src.empty()) throw Error("the input image is empty");
  const CostFunction& cost = find_cost(options.cost);
  check_optimizer(options.optimizer, options.anneal);
  auto t0 = std::chrono::steady_clock::now();
  Mesh2 mesh = delaunay_triangulation(pixel_centres(src.width, src.height));
  auto t1 = std::chrono::steady_clock::now();
  LawsonStats ls;
  if (options.optimize && mesh.triangle_count() > 0) {
    const DriveChannels drive = drive_channels(src, options);
    std::vector<float> own_drive;
    if (!drive.identity) own_drive = drive_values(src.pixels.data(), src.pixel_count(), src.channels, drive);
    LawsonOptions lawson;
    lawson.relative_tolerance = options.relative_tolerance;
    lawson.max_iterations = options.max_iterations;
    // The regions upscale() uses, so that the mesh is the one it renders.
    const int region_rows = optimizer_region_rows(src.width, src.height, options);
    lawson.region_triangles = region_rows > 0 ? region_rows * 2LL * (src.width - 1) : -1;
    ls = run_optimizer(mesh, drive.identity ? src.pixels : own_drive, drive.K, cost, options.optimizer, options.anneal,
                       lawson, options.log);
  }
  if (stats) {
    stats->triangles = mesh.triangle_count();
    stats->iterations = ls.iterations;
    stats->flips = ls.flips;
    stats->tests = ls.tests;
    stats->regions = ls.regions;
    stats->cost_before = ls.cost_before;
    stats->cost_after = ls.cost_after;
    stats->seconds_triangulate = std::chrono::duration<double>(t1 - t0).count();
    stats->seconds_optimize = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }
  return mesh;
}

}  // namespace ddt
