#include "upscale.hpp"

#include "costs.hpp"
#include "cubic_surface.hpp"
#include "error.hpp"
#include "image_io.hpp"
#include "optimizer.hpp"
#include "rasterizer.hpp"
#include "triangulation.hpp"

#include <OpenImageIO/imagebufalgo.h>

#include <chrono>
#include <cstdio>

namespace ddt {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The channels that drive flips: colour channels summed, or their
// luminance (Rec. 601 weights, as in the evaluation's Y) when asked.
std::vector<float> cost_values(const Image& src, const UpscaleOptions& options, int& K) {
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

}  // namespace

Image upscale(const Image& src, int out_width, int out_height, const UpscaleOptions& options, UpscaleStats* stats) {
  if (src.empty() || src.width <= 0 || src.height <= 0) throw Error("the input image is empty");
  if (out_width < 1 || out_height < 1) throw Error("the output size must be at least 1x1");
  const CostFunction& cost = find_cost(options.cost);
  check_render_name(options.render);
  if (options.render == "cubic") slope_limiter_by_name(options.slopes);
  check_optimizer_name(options.optimizer);
  if (options.optimizer == "anneal") check_anneal_options(options.anneal);
  UpscaleStats local;
  auto log = [&](const std::string& line) {
    if (options.log) options.log(line);
  };

  auto t0 = std::chrono::steady_clock::now();
  std::vector<Point2> points(src.pixel_count());
  for (int y = 0; y < src.height; ++y)
    for (int x = 0; x < src.width; ++x) points[static_cast<std::size_t>(y) * src.width + x] = {x + 0.5, y + 0.5};
  Mesh2 mesh = delaunay_triangulation(points);
  local.seconds_triangulate = seconds_since(t0);
  local.triangles = mesh.triangle_count();
  log("triangulate: " + std::to_string(mesh.points.size()) + " points, " + std::to_string(mesh.triangle_count()) +
      " triangles, " + std::to_string(local.seconds_triangulate) + " s");

  t0 = std::chrono::steady_clock::now();
  if (options.optimize && mesh.triangle_count() > 0) {
    int K = 0;
    const std::vector<float> drive = cost_values(src, options, K);
    LawsonOptions lawson;
    lawson.relative_tolerance = options.relative_tolerance;
    lawson.max_iterations = options.max_iterations;
    if (options.log)
      lawson.on_iteration = [&](int iteration, long long flips, double total) {
        char line[160];
        std::snprintf(line, sizeof line, "optimize: iteration %d, %lld flips, cost %.9g", iteration, flips, total);
        log(line);
      };
    LawsonStats ls;
    if (options.optimizer == "anneal") {
      AnnealOptions anneal = options.anneal;
      if (options.log)
        anneal.on_step = [&](int step, double temperature, long long flips, double total) {
          char line[160];
          std::snprintf(line, sizeof line, "anneal: step %d, T %.4g, %lld flips, cost %.9g", step, temperature,
                        flips, total);
          log(line);
        };
      const AnnealStats as = optimize_anneal(mesh, drive, K, cost, anneal, lawson);
      ls = as.lawson;  // the final Lawson pass; totals cover the whole run
      ls.flips += as.accepted;
      ls.cost_before = as.cost_before;
      ls.cost_after = as.cost_after;
    } else {
      ls = optimize_lawson(mesh, drive, K, cost, lawson);
    }
    local.iterations = ls.iterations;
    local.flips = ls.flips;
    local.cost_before = ls.cost_before;
    local.cost_after = ls.cost_after;
  }
  local.seconds_optimize = seconds_since(t0);
  if (options.optimize) {
    char line[200];
    std::snprintf(line, sizeof line, "optimize: cost %s, %d iterations, %lld flips, cost %.9g -> %.9g, %.3f s",
                  cost.name, local.iterations, local.flips, local.cost_before, local.cost_after,
                  local.seconds_optimize);
    log(line);
  }

  t0 = std::chrono::steady_clock::now();
  RenderGrid grid;
  grid.width = out_width;
  grid.height = out_height;
  grid.scale_x = static_cast<double>(out_width) / src.width;
  grid.scale_y = static_cast<double>(out_height) / src.height;
  RenderStats rs;
  std::vector<float> gradients;
  if (options.render == "cubic") gradients = grid_gradients(src, slope_limiter_by_name(options.slopes));
  Image out = render_mesh(mesh, src.pixels, src.channels, grid, &rs, true, 0.0f,
                          options.render == "cubic" ? &gradients : nullptr);
  local.seconds_render = seconds_since(t0);
  log("render: " + std::to_string(out_width) + "x" + std::to_string(out_height) + ", " +
      std::to_string(rs.triangles) + " + " + std::to_string(rs.rim_triangles) + " rim triangles, " +
      std::to_string(local.seconds_render) + " s");
  if (stats) *stats = local;
  return out;
}

bool upscale(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, int out_width, int out_height,
             const UpscaleOptions& options, OIIO::ROI roi) {
  try {
    if (!roi.defined()) roi = src.roi();
    OIIO::ImageBuf cropped = OIIO::ImageBufAlgo::cut(src, roi);
    Image in = image_from_buf(cropped);
    UpscaleOptions opts = options;
    if (opts.alpha_channel < 0) opts.alpha_channel = src.spec().alpha_channel;
    dst = buf_from_image(upscale(in, out_width, out_height, opts));
    return true;
  } catch (const std::exception& e) {
    dst.errorfmt("{}", e.what());
    return false;
  }
}

}  // namespace ddt
