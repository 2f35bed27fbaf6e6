#include "consistency/consistent_reconstruction.hpp"

#include "util/error.hpp"
#include "consistency/grid_surface.hpp"
#include "consistency/halo_limit.hpp"
#include "consistency/step_edges.hpp"
#include "image/rasterizer.hpp"
#include "util/timing.hpp"

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
  // render of v on the mesh); the rasterizer adds each step's surface to
  // the output as drawn (exact ownership, fast on lattice meshes), and the
  // new residual is the output's own.
  if (options.mesh_steps > 0) {
    RenderGrid surface;
    surface.width = out.width;
    surface.height = out.height;
    surface.scale_x = static_cast<double>(out.width) / W;
    surface.scale_y = static_cast<double>(out.height) / H;
    std::vector<float> values(residual.size());
    double norm = norm2(residual);
    for (int k = 0; k < options.mesh_steps; ++k) {
      std::transform(residual.begin(), residual.end(), values.begin(), [](double v) { return static_cast<float>(v); });
      add_mesh_render_into(out, 0, mesh, values, C, surface);
      acquisition.apply(out, 0, 0, H, acquired);
      subtract_from(src, acquired);
      const double now = norm2(acquired);
      // Kept while it lowers the residual's 2-norm by 1 % or more; else
      // taken back (to rounding), and the residual is the output's again.
      if (!(now < norm * (1 - 0.01))) {
        for (float& v : values) v = -v;
        add_mesh_render_into(out, 0, mesh, values, C, surface);
        acquisition.apply(out, 0, 0, H, residual);
        subtract_from(src, residual);
        break;
      }
      residual.swap(acquired);
      norm = now;
      ++local.mesh_steps;
    }
  }
  if (options.mesh_done) options.mesh_done();
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
  // The grid correction, then under the box model a footprint crossed by
  // one straight edge drawn as that edge (step_edges.hpp), then the halo
  // limit: each reads and writes its own footprint's pixels only, so they
  // run band by band, a band of input rows at a time.
  const FootprintPixels footprints = footprint_pixels(W, H, out.width, out.height);
  const bool draw_edges = options.step_edges && options.model.kind == AcquisitionModel::Kind::box;
  const StepEdgeRenderer edges(src);
  const HaloLimiter halos(src);
  auto finish_rows = [&](int first, int end) {
    grid.add_to(out, delta_grid, footprints.first_y[first], footprints.first_y[end]);
    if (draw_edges) local.step_edge_footprints += edges.render(out, first, end);
    if (options.limit_halos) local.halo_footprints += halos.limit(out, first, end);
  };
  auto hand_out = [&](int first, int end) {  // output rows
    if (!options.output_rows || first >= end) return;
    Image rows;
    rows.width = out.width, rows.height = end - first, rows.channels = C;
    const std::ptrdiff_t row_floats = static_cast<std::ptrdiff_t>(out.width) * C;
    rows.pixels.assign(out.pixels.begin() + row_floats * first, out.pixels.begin() + row_floats * end);
    options.output_rows(std::move(rows), first);
  };
  // Box at integer scales acquires exactly the footprint means the last
  // steps keep; elsewhere they move the acquisition, and one more exact
  // correction on the grid follows, over the whole image.
  const bool kept_exactly =
      options.model.kind == AcquisitionModel::Kind::box && out.width % W == 0 && out.height % H == 0;
  const int band_out_rows = std::max(1, options.output_band_rows);
  if (kept_exactly && options.output_rows) {
    const int band = static_cast<int>(std::max(1LL, static_cast<long long>(band_out_rows) * H / out.height));
    for (int first = 0; first < H; first += band) {
      const int end = std::min(H, first + band);
      finish_rows(first, end);
      hand_out(footprints.first_y[first], footprints.first_y[end]);
    }
  } else {
    finish_rows(0, H);
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
    for (int first = 0; first < out.height; first += band_out_rows)
      hand_out(first, std::min(out.height, first + band_out_rows));
  }
  local.seconds_render = seconds_since(t0);
  if (stats) *stats = local;
}

}  // namespace ddt
