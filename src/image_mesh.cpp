#include "image_mesh.hpp"

#include "costs.hpp"
#include "error.hpp"
#include "optimizer.hpp"
#include "triangulation.hpp"

#include <chrono>

namespace ddt {

std::vector<float> cost_channel_values(const Image& src, const UpscaleOptions& options, int& K) {
  std::vector<int> colour;
  for (int c = 0; c < src.channels; ++c)
    if (c != options.alpha_channel) colour.push_back(c);
  const std::size_t n = src.pixel_count();
  if (options.luma_cost && colour.size() >= 3) {
    K = 1;
    std::vector<float> luma(n);
    for (std::size_t i = 0; i < n; ++i) {
      const float* px = &src.pixels[i * src.channels];
      luma[i] = 0.299f * px[colour[0]] + 0.587f * px[colour[1]] + 0.114f * px[colour[2]];
    }
    return luma;
  }
  if (colour.size() > static_cast<std::size_t>(max_cost_channels))
    throw Error("the cost takes at most " + std::to_string(max_cost_channels) + " channels; this image has " +
                std::to_string(colour.size()) + " (use --cost-channel luma)");
  if (colour.empty()) colour.push_back(0);  // alpha alone: let it drive
  K = static_cast<int>(colour.size());
  std::vector<float> out(n * K);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < K; ++k) out[i * K + k] = src.pixels[i * src.channels + colour[k]];
  return out;
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
  auto t0 = std::chrono::steady_clock::now();
  Mesh2 mesh = delaunay_triangulation(pixel_centres(src.width, src.height));
  auto t1 = std::chrono::steady_clock::now();
  LawsonStats ls;
  if (options.optimize && mesh.triangle_count() > 0) {
    int K = 0;
    const std::vector<float> drive = cost_channel_values(src, options, K);
    LawsonOptions lawson;
    lawson.relative_tolerance = options.relative_tolerance;
    lawson.max_iterations = options.max_iterations;
    ls = optimize_lawson(mesh, drive, K, cost, lawson);
  }
  if (stats) {
    stats->triangles = mesh.triangle_count();
    stats->iterations = ls.iterations;
    stats->flips = ls.flips;
    stats->cost_before = ls.cost_before;
    stats->cost_after = ls.cost_after;
    stats->seconds_triangulate = std::chrono::duration<double>(t1 - t0).count();
    stats->seconds_optimize = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }
  return mesh;
}

}  // namespace ddt
