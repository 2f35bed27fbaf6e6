#include "consistency/consistent_reconstruction.hpp"

#include "util/error.hpp"
#include "consistency/grid_surface.hpp"
#include "consistency/halo_limit.hpp"
#include "consistency/step_edges.hpp"
#include "image/rasterizer.hpp"
#include "util/timing.hpp"
#include "consistency/input_statistics.hpp"

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

// The rows of a problem that may be a band of the whole image.
struct Rows {
  int top, end;          // input rows held, absolute
  int height;            // the whole image's
  int out_origin, out_end, out_height;
};

// src - acquisition of `out` on the band's input rows (src's rows), 0 on
// the rows whose footprints reach beyond the output rows held (at a band's
// cut: its margin).
void residual_of(const Image& out, const Image& src, const Acquisition& acquisition, const Rows& rows,
                 std::vector<double>& residual) {
  const auto [a, b] = acquisition.rows_covered(rows.out_origin, rows.out_end, rows.top, rows.end);
  const std::size_t row_size = static_cast<std::size_t>(src.width) * src.channels;
  residual.assign(row_size * (rows.end - rows.top), 0.0);
  if (a >= b) return;
  std::vector<double> acquired;
  acquisition.apply(out, rows.out_origin, a, b, acquired);
  const std::size_t offset = row_size * (a - rows.top);
  for (std::size_t i = 0; i < acquired.size(); ++i)
    residual[offset + i] = double(src.pixels[offset + i]) - acquired[i];
}

bool kept_exactly(const AcquisitionModel& model, int W, int H, int out_w, int out_h) {
  return model.kind == AcquisitionModel::Kind::box && out_w % W == 0 && out_h % H == 0;
}

}  // namespace

void make_consistent(Image& out, const Mesh2& mesh, const Image& src, const ConsistencyOptions& options,
                     ConsistencyStats* stats) {
  if (options.model.kind == AcquisitionModel::Kind::point) return;
  const int W = src.width, C = src.channels;
  if (C > max_channels) throw Error("the consistent reconstruction takes at most 16 channels");
  if (mesh.points.size() != static_cast<std::size_t>(W) * src.height)
    throw Error("the consistent reconstruction: the mesh is not the pixel grid");
  const RowBand& band = options.band;
  const Rows rows{band.src_top, band.src_top + src.height, band.image_height > 0 ? band.image_height : src.height,
                  band.out_origin, band.out_origin + out.height, band.out_height > 0 ? band.out_height : out.height};
  const int H = rows.height, out_h = rows.out_height;
  if (rows.top < 0 || rows.end > H || rows.out_origin < 0 || rows.out_end > out_h)
    throw Error("the consistent reconstruction: a band outside its image");
  InputStatistics own;
  if (!options.statistics) own = input_statistics(src);
  const InputStatistics& statistics = options.statistics ? *options.statistics : own;
  ConsistencyStats local;

  auto t0 = std::chrono::steady_clock::now();
  const Acquisition acquisition(options.model, W, H, out.width, out_h);
  const GridSurface grid(W, H, out.width, out_h, options.model);
  local.seconds_operator = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  std::vector<double> residual;
  residual_of(out, src, acquisition, rows, residual);
  local.residual_before = max_abs(residual);
  // Back-projection on the mesh: x += r - A x, with A v = acquire(linear
  // render of v on the mesh); the rasterizer adds each step's surface to
  // the output as drawn (exact ownership, fast on lattice meshes), and the
  // new residual is the output's own. A fixed number of steps, not one
  // decided by the whole image's residual, so that bands decide alike
  // (docs/consistency.md: every step was kept on Set5 and Set14).
  if (options.mesh_steps > 0) {
    RenderGrid surface;
    surface.width = out.width;
    surface.height = out_h;
    surface.scale_x = static_cast<double>(out.width) / W;
    surface.scale_y = static_cast<double>(out_h) / H;
    surface.first_row = rows.out_origin;
    surface.rows = out.height;
    std::vector<float> values(residual.size());
    for (int k = 0; k < options.mesh_steps; ++k) {
      std::transform(residual.begin(), residual.end(), values.begin(), [](double v) { return static_cast<float>(v); });
      add_mesh_render_into(out, 0, mesh, values, C, surface);
      residual_of(out, src, acquisition, rows, residual);
      ++local.mesh_steps;
    }
  }
  if (options.mesh_done) options.mesh_done();
  local.residual_mesh = max_abs(residual);
  std::vector<double> delta_grid, acquired;
  grid.solve(residual, delta_grid, C, rows.top, rows.end);
  {
    grid.acquire(delta_grid, acquired, C, rows.top, rows.end);
    const auto [a, b] = acquisition.rows_covered(rows.out_origin, rows.out_end, rows.top, rows.end);
    const std::size_t row_size = static_cast<std::size_t>(W) * C;
    // Rows within the solve's reach of a band's cut are its margin.
    const int first = rows.top > 0 ? a + grid.reach() : a, end = rows.end < H ? b - grid.reach() : b;
    for (std::size_t i = row_size * std::max(0, first - rows.top); i < row_size * std::max(0, end - rows.top); ++i)
      local.residual_after = std::max(local.residual_after, std::abs(residual[i] - acquired[i]));
  }
  local.seconds_solve = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  // The grid correction, then under the box model a footprint crossed by
  // one straight edge drawn as that edge (step_edges.hpp), then the halo
  // limit: each reads and writes its own footprint's pixels only, so they
  // run band by band, a band of input rows at a time.
  const FootprintPixels footprints = footprint_pixels(W, H, out.width, out_h);
  const bool draw_edges = options.step_edges && options.model.kind == AcquisitionModel::Kind::box;
  const StepEdgeRenderer edges(src, statistics, band);
  const HaloLimiter halos(src, statistics, band);
  auto finish_rows = [&](int first, int end) {  // input rows
    grid.add_to(out, delta_grid, footprints.first_y[first], footprints.first_y[end], rows.out_origin, rows.top);
    if (draw_edges) local.step_edge_footprints += edges.render(out, first, end);
    if (options.limit_halos) local.halo_footprints += halos.limit(out, first, end);
  };
  auto hand_out = [&](int first, int end) {  // output rows
    if (!options.output_rows || first >= end) return;
    Image part;
    part.width = out.width, part.height = end - first, part.channels = C;
    const std::ptrdiff_t row_floats = static_cast<std::ptrdiff_t>(out.width) * C;
    part.pixels.assign(out.pixels.begin() + row_floats * (first - rows.out_origin),
                       out.pixels.begin() + row_floats * (end - rows.out_origin));
    options.output_rows(std::move(part), first);
  };
  // Box at integer scales acquires exactly the footprint means the last
  // steps keep; elsewhere they move the acquisition, and one more exact
  // correction on the grid follows.
  const bool exact = kept_exactly(options.model, W, H, out.width, out_h);
  const int band_out_rows = std::max(1, options.output_band_rows);
  if (exact && options.output_rows) {
    const int step = static_cast<int>(std::max(1LL, static_cast<long long>(band_out_rows) * H / out_h));
    for (int first = rows.top; first < rows.end; first += step) {
      const int end = std::min(rows.end, first + step);
      finish_rows(first, end);
      hand_out(footprints.first_y[first], footprints.first_y[end]);
    }
  } else {
    finish_rows(rows.top, rows.end);
    if (!exact) {
      std::vector<double> rest, delta;
      residual_of(out, src, acquisition, rows, rest);
      grid.solve(rest, delta, C, rows.top, rows.end);
      grid.add_to(out, delta, -1, -1, rows.out_origin, rows.top);
    }
    for (int first = rows.out_origin; first < rows.out_end; first += band_out_rows)
      hand_out(first, std::min(rows.out_end, first + band_out_rows));
  }
  local.seconds_render = seconds_since(t0);
  if (stats) *stats = local;
}

int triangle_rows(const Mesh2& mesh) {
  int span = 0;
  for (std::size_t t = 0; t + 2 < mesh.tri.size(); t += 3) {
    const double y0 = mesh.points[mesh.tri[t]].y, y1 = mesh.points[mesh.tri[t + 1]].y,
                 y2 = mesh.points[mesh.tri[t + 2]].y;
    span = std::max(span, static_cast<int>(std::ceil(std::max({y0, y1, y2}) - std::min({y0, y1, y2}))));
  }
  return span;
}

int consistency_margin_needed(int span, const AcquisitionModel& model, int W, int H, int out_w, int out_h,
                              int mesh_steps) {
  if (model.kind == AcquisitionModel::Kind::point) return 0;
  const int a = Acquisition(model, W, H, out_w, out_h).reach();
  const int g = GridSurface(W, H, out_w, out_h, model).reach();
  // Backwards from a kept row: the halo limit and the straight edges read
  // 2 rows of the input around it; the grid correction's bilinear surface
  // a row, its solve g rows of residual, each residual a rows of output;
  // each mesh step a triangle's height of the step before; the rendered
  // surface a triangle's height and the cubic's gradients 2 rows. Where
  // the last steps move the acquisition, one more correction on top.
  const int correction = 1 + g + a;
  return 2 + correction + mesh_steps * (span + 1 + a) + span + 3 +
         (kept_exactly(model, W, H, out_w, out_h) ? 0 : correction + 2);
}

}  // namespace ddt
