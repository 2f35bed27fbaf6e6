#include "consistency/consistent_reconstruction.hpp"

#include "util/error.hpp"
#include "util/huge_pages.hpp"
#include "consistency/grid_surface.hpp"
#include "consistency/halo_limit.hpp"
#include "consistency/step_edges.hpp"
#include "image/rasterizer.hpp"
#include "util/timing.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ddt {
namespace {

constexpr int max_channels = 16;

double max_abs(const std::vector<double>& a) {
  double m = 0;
  for (double v : a) m = std::max(m, std::abs(v));
  return m;
}

double norm2(const std::vector<double>& a) {
  double m = 0;
  for (double v : a) m += v * v;
  return m;
}

// src - acquisition: what the output still fails to reproduce.
void subtract_from(const Image& src, std::vector<double>& acquired) {
  for (std::size_t i = 0; i < acquired.size(); ++i) acquired[i] = double(src.pixels[i]) - acquired[i];
}

void add_image(Image& out, const Image& add) {
  tbb::parallel_for(0, out.height, [&](int Y) {
    float* o = &out.pixels[out.index(0, Y)];
    const float* a = &add.pixels[add.index(0, Y)];
    for (std::size_t i = 0, n = static_cast<std::size_t>(out.width) * out.channels; i < n; ++i) o[i] += a[i];
  });
}

}  // namespace

void make_consistent(Image& out, const Mesh2& mesh, const Image& src, const ConsistencyOptions& options,
                     ConsistencyStats* stats) {
  if (options.model.kind == AcquisitionModel::Kind::point) return;
  const int W = src.width, H = src.height, C = src.channels;
  if (C > max_channels) throw Error("the consistent reconstruction takes at most 16 channels");
  if (mesh.points.size() != static_cast<std::size_t>(W) * H)
    throw Error("the consistent reconstruction: the mesh is not the pixel grid");
  ConsistencyStats local;

  auto t0 = std::chrono::steady_clock::now();
  const Acquisition acquisition(options.model, W, H, out.width, out.height);
  const GridSurface grid(W, H, out.width, out.height, options.model);
  local.seconds_operator = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  std::vector<double> residual, acquired;
  acquisition.apply(out, 0, 0, H, residual);
  subtract_from(src, residual);
  local.residual_before = max_abs(residual);
  // Back-projection on the mesh: x += r - A x, with A v = acquire(linear
  // render of v on the mesh); the rasterizer draws each step's surface
  // (exact ownership, fast on lattice meshes) and the step is added as
  // drawn, so its acquisition is exactly what leaves the residual.
  if (options.mesh_steps > 0) {
    RenderGrid surface;
    surface.width = out.width;
    surface.height = out.height;
    surface.scale_x = static_cast<double>(out.width) / W;
    surface.scale_y = static_cast<double>(out.height) / H;
    Image step(out.width, out.height, C);
    std::vector<float> values;
    assign_huge(values, residual.size(), 0.0f);
    double norm = norm2(residual);
    for (int k = 0; k < options.mesh_steps; ++k) {
      std::transform(residual.begin(), residual.end(), values.begin(), [](double v) { return static_cast<float>(v); });
      render_mesh_into(step, 0, mesh, values, C, surface);
      acquisition.apply(step, 0, 0, H, acquired);
      for (std::size_t i = 0; i < acquired.size(); ++i) acquired[i] = residual[i] - acquired[i];
      const double now = norm2(acquired);
      // Kept while it lowers the residual's 2-norm by 1 % or more.
      if (!(now < norm * (1 - 0.01))) break;
      add_image(out, step);
      residual.swap(acquired);
      norm = now;
      ++local.mesh_steps;
    }
  }
  local.residual_mesh = max_abs(residual);
  std::vector<double> delta_grid;
  grid.solve(residual, delta_grid, C);
  {
    grid.acquire(delta_grid, acquired, C);
    for (std::size_t i = 0; i < acquired.size(); ++i)
      local.residual_after = std::max(local.residual_after, std::abs(residual[i] - acquired[i]));
  }
  local.seconds_solve = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  grid.add_to(out, delta_grid);
  // Under the box model a footprint crossed by one straight edge shows
  // where the edge passes inside it: drawn as that edge (step_edges.hpp).
  if (options.step_edges && options.model.kind == AcquisitionModel::Kind::box)
    local.step_edge_footprints = render_step_edges(out, src);
  if (options.limit_halos) local.halo_footprints = limit_halos(out, src);
  // Where these moved a footprint's acquisition (models other than box,
  // non-integer scales), one more exact correction on the grid; box at
  // integer scales acquires exactly the footprint means they kept.
  const bool kept_exactly =
      options.model.kind == AcquisitionModel::Kind::box && out.width % W == 0 && out.height % H == 0;
  if (!kept_exactly && local.halo_footprints + local.step_edge_footprints > 0) {
    std::vector<double> rest;
    acquisition.apply(out, 0, 0, H, rest);
    subtract_from(src, rest);
    if (max_abs(rest) > 10 * options.tolerance) {
      std::vector<double> delta;
      grid.solve(rest, delta, C);
      grid.add_to(out, delta);
      ++local.halo_passes;
    }
  }
  local.seconds_render = seconds_since(t0);
  if (stats) *stats = local;
}

}  // namespace ddt
