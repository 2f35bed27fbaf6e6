#include "consistency/consistent_reconstruction.hpp"

#include "util/error.hpp"
#include "consistency/grid_surface.hpp"
#include "consistency/halo_limit.hpp"
#include "consistency/step_edges.hpp"
#include "image/rasterizer.hpp"
#include "util/prefaulted_image.hpp"
#include "util/timing.hpp"
#include "consistency/input_statistics.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

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

void check_problem(const Mesh2& mesh, const Image& src) {
  if (src.channels > max_channels) throw Error("the consistent reconstruction takes at most 16 channels");
  if (mesh.points.size() != static_cast<std::size_t>(src.width) * src.height)
    throw Error("the consistent reconstruction: the mesh is not the pixel grid");
}

// The whole input's statistics: the caller's (bands share them), or src's
// own, computed into `own`.
const InputStatistics& statistics_of(const ConsistencyOptions& options, const Image& src, InputStatistics& own) {
  if (options.statistics) return *options.statistics;
  own = input_statistics(src);
  return own;
}

// The output grid of an image of W x H enlarged to out_w x out_h, all rows.
RenderGrid output_grid(int W, int H, int out_w, int out_h) {
  RenderGrid grid;
  grid.width = out_w;
  grid.height = out_h;
  grid.scale_x = static_cast<double>(out_w) / W;
  grid.scale_y = static_cast<double>(out_h) / H;
  return grid;
}

// Hands output rows [first, end) of `held` (which holds output rows from
// `origin`) to options.output_rows, a copy of each.
void hand_out(const Image& held, int origin, int first, int end, const ConsistencyOptions& options) {
  if (!options.output_rows || first >= end) return;
  Image part;
  part.width = held.width, part.height = end - first, part.channels = held.channels;
  const std::ptrdiff_t row_floats = static_cast<std::ptrdiff_t>(held.width) * held.channels;
  part.pixels.assign(held.pixels.begin() + row_floats * (first - origin),
                     held.pixels.begin() + row_floats * (end - origin));
  options.output_rows(std::move(part), first);
}

bool kept_exactly(const AcquisitionModel& model, int W, int H, int out_w, int out_h) {
  return model.kind == AcquisitionModel::Kind::box && out_w % W == 0 && out_h % H == 0;
}

}  // namespace

void make_consistent(Image& out, const Mesh2& mesh, const Image& src, const ConsistencyOptions& options,
                     ConsistencyStats* stats) {
  if (options.model.kind == AcquisitionModel::Kind::point) return;
  const int W = src.width, C = src.channels;
  check_problem(mesh, src);
  const RowBand& band = options.band;
  const Rows rows{band.src_top, band.src_top + src.height, band.image_height > 0 ? band.image_height : src.height,
                  band.out_origin, band.out_origin + out.height, band.out_height > 0 ? band.out_height : out.height};
  const int H = rows.height, out_h = rows.out_height;
  if (rows.top < 0 || rows.end > H || rows.out_origin < 0 || rows.out_end > out_h)
    throw Error("the consistent reconstruction: a band outside its image");
  InputStatistics own;
  const InputStatistics& statistics = statistics_of(options, src, own);
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
    const RenderPlan plan(mesh, output_grid(W, H, out.width, out_h));
    std::vector<float> values(residual.size());
    for (int k = 0; k < options.mesh_steps; ++k) {
      std::transform(residual.begin(), residual.end(), values.begin(), [](double v) { return static_cast<float>(v); });
      add_mesh_render_into(out, 0, plan, values, C, rows.out_origin, out.height);
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
      hand_out(out, rows.out_origin, footprints.first_y[first], footprints.first_y[end], options);
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
      hand_out(out, rows.out_origin, first, std::min(rows.out_end, first + band_out_rows), options);
  }
  local.seconds_render = seconds_since(t0);
  if (stats) *stats = local;
}

bool make_consistent_streams(const AcquisitionModel& model, int W, int H, int out_w, int out_h) {
  return kept_exactly(model, W, H, out_w, out_h);
}

namespace {

// Rows [origin, origin + capacity) of an array at input resolution
// (row_size values a row), for a wavefront: rows it has left behind make
// room for the rows ahead.
template <typename T>
struct SlidingRows {
  SlidingRows(std::size_t row_size, int capacity)
      : values(prefaulted_zeros<T>(row_size * capacity)), row_size(row_size), capacity(capacity) {}
  std::vector<T> values;
  std::size_t row_size;
  int capacity, origin = 0;

  T* row(int y) { return values.data() + row_size * (y - origin); }
  // Rows up to `end` made room for, keeping rows from `keep` on; more
  // rows held when the wavefront's reach has grown.
  void make_room(int end, int keep) {
    if (end - origin <= capacity) return;
    std::copy(values.begin() + static_cast<std::ptrdiff_t>(row_size * (keep - origin)), values.end(), values.begin());
    origin = keep;
    if (end - origin > capacity) {
      capacity = end - origin;
      prefaulted_resize(values, row_size * capacity, T{});  // exactly: resizing alone would double the vector
    }
  }
  std::vector<T> rows(int first, int end) const {
    return {values.begin() + static_cast<std::ptrdiff_t>(row_size * (first - origin)),
            values.begin() + static_cast<std::ptrdiff_t>(row_size * (end - origin))};
  }
};

}  // namespace

// The whole image's one mesh.
class OneMesh final : public WavefrontMeshes {
 public:
  OneMesh(const Mesh2& mesh, const std::vector<float>& values, int C, int input_rows, const RenderGrid& grid)
      : values_(values), C_(C), height_(grid.height), input_rows_(input_rows), plan_(std::in_place, mesh, grid),
        reach_(ddt::triangle_rows(mesh)), vertices_(static_cast<index_t>(mesh.points.size())) {}
  int prepare(int) override { return height_; }
  int triangle_rows() const override { return reach_; }
  bool slides() const override { return plan_->adds_windows_of_values(); }
  int window_boundary(int row) const override { return plan_->window_boundary(row); }
  void draw(Image& into, int at, int first, int end, const VertexValues* gradients, RenderStats* stats) override {
    if (gradients) render_mesh_into(into, at, *plan_, values_, C_, first, end - first, *gradients, stats);
    else render_mesh_into(into, at, *plan_, values_, C_, first, end - first, stats);
  }
  void add(Image& into, int at, int first, int end, const std::vector<float>& rows, index_t first_vertex,
           index_t end_vertex) override {
    if (slides())
      return add_mesh_render_into(into, at, *plan_, VertexValues{rows.data(), first_vertex, end_vertex}, C_, first,
                                  end - first);
    // A mesh without triangles or with a hull not convex reads every value.
    if (first_vertex != 0 || end_vertex < vertices_) throw Error("the consistent reconstruction: values missing");
    add_mesh_render_into(into, at, *plan_, rows, C_, first, end - first);
  }
  void release(int row) override {
    if (row >= height_) plan_.reset();
  }
  // The one mesh is made: it reads no input rows.
  int first_input_row() const override { return input_rows_; }

 private:
  const std::vector<float>& values_;
  int C_, height_, input_rows_;
  std::optional<RenderPlan> plan_;
  int reach_;
  index_t vertices_;
};

void make_consistent_streamed(int out_width, int out_height, const std::vector<float>& values,
                              const GradientRows& gradients, const Mesh2& mesh, const Image& src,
                              const ConsistencyOptions& options, ConsistencyStats* stats, RenderStats* render_stats) {
  if (!options.output_rows) throw Error("the consistent reconstruction: nowhere to hand the rows");
  if (options.band.image_height > 0 || options.band.out_height > 0)
    throw Error("the consistent reconstruction: a streamed surface is the whole image's");
  const int W = src.width, H = src.height, C = src.channels;
  const RenderGrid surface_grid = output_grid(W, H, out_width, out_height);
  if (!make_consistent_streams(options.model, W, H, out_width, out_height)) {
    const auto t = std::chrono::steady_clock::now();
    Image out(out_width, out_height, C);
    const std::vector<float> all = gradients ? gradients(0, H) : std::vector<float>();
    render_mesh_into(out, 0, mesh, values, C, surface_grid, render_stats, true, gradients ? &all : nullptr);
    const double surface_seconds = seconds_since(t);
    make_consistent(out, mesh, src, options, stats);
    if (stats) stats->seconds_surface = surface_seconds;
    return;
  }
  check_problem(mesh, src);
  const auto t = std::chrono::steady_clock::now();
  OneMesh one(mesh, values, C, H, surface_grid);
  const double plan_seconds = seconds_since(t);
  InputRows input(src);
  make_consistent_streamed(out_width, out_height, one, gradients, input, options, stats, render_stats);
  if (stats) stats->seconds_operator += plan_seconds;
}

void make_consistent_streamed(int out_width, int out_height, WavefrontMeshes& meshes, const GradientRows& gradients,
                              InputRows& input, const ConsistencyOptions& options, ConsistencyStats* stats,
                              RenderStats* render_stats) {
  if (!options.output_rows) throw Error("the consistent reconstruction: nowhere to hand the rows");
  if (options.band.image_height > 0 || options.band.out_height > 0)
    throw Error("the consistent reconstruction: a streamed surface is the whole image's");
  const int W = input.width(), H = input.height(), C = input.channels();
  if (!make_consistent_streams(options.model, W, H, out_width, out_height))
    throw Error("the consistent reconstruction: this model and scale do not stream");
  if (C > max_channels) throw Error("the consistent reconstruction takes at most 16 channels");
  if (!options.statistics && !input.whole())
    throw Error("the consistent reconstruction: an input read by rows needs the whole input's statistics");
  double surface_seconds = 0;
  InputStatistics own;
  const InputStatistics& statistics = options.statistics ? *options.statistics : statistics_of(options, *input.whole(), own);
  ConsistencyStats local;
  auto t0 = std::chrono::steady_clock::now();
  const Acquisition acquisition(options.model, W, H, out_width, out_height);
  const GridSurface grid(W, H, out_width, out_height, options.model);
  const FootprintPixels footprints = footprint_pixels(W, H, out_width, out_height);
  const std::vector<int>& row_of = footprints.first_y;  // output rows of input row j: [row_of[j], row_of[j + 1])
  local.seconds_operator = seconds_since(t0);

  // Input rows [0, drawn) have their output rows drawn, [0, residual[k]) the
  // residual after k mesh steps, [0, stepped[k]) k mesh steps added,
  // [0, solved) the grid correction, [0, finished) the last steps done and
  // handed out, [0, checked) the solve's residual measured. A step runs on
  // the rows whose inputs are finished: the residual on its footprints
  // (box: its own output rows), a mesh step within a triangle's height of
  // the residual before it (the vertices of the triangles crossing a row),
  // the grid solve within its reach, the grid correction a row (its
  // bilinear surface), the measure two.
  // The reach of a mesh step grows with the triangles of the meshes made.
  const int K = options.mesh_steps, solve_reach = grid.reach();
  int mesh_reach = 0, lag = 0;
  auto update_reach = [&] {
    mesh_reach = meshes.triangle_rows() + 2;
    lag = K * mesh_reach + solve_reach + 2;
  };
  // Input rows drawn at a time: the output rows held are the lag and a step
  // (docs/performance.md, "The wavefront's step").
  constexpr int step = 16;
  const auto t_first = std::chrono::steady_clock::now();
  meshes.prepare(0);  // the first mesh (band): part of the surface's time, as the later ones
  surface_seconds += seconds_since(t_first);
  update_reach();
  int drawn = 0, solved = 0, finished = 0, checked = 0;
  std::vector<int> residual_done(K + 1, 0), stepped(K + 1, 0);
  const std::size_t row_size = static_cast<std::size_t>(W) * C;
  // The values of mesh step k + 1 (the residual after k steps, as floats,
  // by vertex: a lattice's vertex is its pixel), from the rows its render
  // still reads (a triangle's height before the rows it adds) to the rows
  // written; the last residual and the grid correction, by rows.
  // A lattice's mesh is drawn from windows of rows of values; other meshes
  // (no triangles, a hull not convex) from all of them.
  const bool slide = meshes.slides();
  const int step_rows = slide ? std::min(H, 2 * step + 4 * mesh_reach + 16) : H;
  std::vector<SlidingRows<float>> step_values(K, SlidingRows<float>(row_size, step_rows));
  const int sliding_rows = std::min(H, lag + solve_reach + step + 8);
  SlidingRows<double> last_residual(row_size, sliding_rows), delta(row_size, sliding_rows);
  // The cubic surface's gradients, from the rows its next rows reach to the
  // rows made: [gradient_rows.origin, gradients_made).
  SlidingRows<float> gradient_rows(gradients ? 2 * row_size : 0, slide ? std::min(H, 2 * step + 2 * mesh_reach + 16) : H);
  int gradients_made = 0;
  // The input row whose footprint holds output row Y.
  auto input_row = [&](int Y) {
    return static_cast<int>(std::upper_bound(row_of.begin(), row_of.end(), Y) - row_of.begin()) - 1;
  };
  std::vector<double> acquired, solved_rows, acquired_delta;
  // Output rows [window_origin, window_origin + window.height) of which
  // [row_of[finished], drawn_rows) are in use; finished rows make room.
  Image window = prefaulted_image(out_width, std::min(out_height, row_of[std::min(H, lag + step + 4)] + 1), C);
  local.held_rows = window.height;
  int window_origin = 0, drawn_rows = 0;
  bool meshes_done = false;
  const int band_out_rows = std::max(1, options.output_band_rows);
  if (options.progress) options.progress->begin("consistency", H);

  double solve_seconds = 0, finish_seconds = 0;
  while (finished < H) {
    auto t = std::chrono::steady_clock::now();
    // The surface's next rows, cut where its render keeps the whole
    // image's bits; then the input rows whose footprints are all drawn.
    if (drawn < H) {
      const int ready_end = meshes.prepare(drawn_rows);
      update_reach();
      const int wanted = std::min(ready_end, row_of[std::min(H, drawn + step)]);
      const int cut = std::max(drawn_rows + 1, std::min(ready_end, meshes.window_boundary(wanted)));
      if (cut - window_origin > window.height) {
        const int keep = row_of[finished];
        const std::ptrdiff_t row_floats = static_cast<std::ptrdiff_t>(out_width) * C;
        std::copy(window.pixels.begin() + row_floats * (keep - window_origin),
                  window.pixels.begin() + row_floats * (drawn_rows - window_origin), window.pixels.begin());
        window_origin = keep;
        if (cut - window_origin > window.height) {  // the reach has grown
          Image wider = prefaulted_image(out_width, cut - window_origin, C);
          std::copy(window.pixels.begin(), window.pixels.begin() + row_floats * (drawn_rows - window_origin),
                    wider.pixels.begin());
          window = std::move(wider);
          local.held_rows = std::max(local.held_rows, window.height);
        }
      }
      RenderStats rows_stats;
      if (gradients) {
        // The rows of vertices of the triangles (and rim slabs) these output rows cross.
        const int top = slide ? std::max(0, input_row(drawn_rows) - mesh_reach - 1) : 0;
        const int bottom = slide ? std::min(H, input_row(cut - 1) + mesh_reach + 2) : H;
        if (bottom > gradients_made) {
          gradient_rows.make_room(bottom, std::min(top, gradients_made));
          const std::vector<float> made = gradients(gradients_made, bottom);
          if (made.size() != gradient_rows.row_size * (bottom - gradients_made))
            throw Error("the consistent reconstruction: gradients of another grid");
          std::copy(made.begin(), made.end(), gradient_rows.row(gradients_made));
          gradients_made = bottom;
        }
        const VertexValues held{gradient_rows.values.data(), index_t(gradient_rows.origin) * W,
                                index_t(gradients_made) * W};
        meshes.draw(window, drawn_rows - window_origin, drawn_rows, cut, &held, &rows_stats);
      } else {
        meshes.draw(window, drawn_rows - window_origin, drawn_rows, cut, nullptr, &rows_stats);
      }
      if (render_stats) *render_stats = rows_stats;
      drawn_rows = cut;
      while (drawn < H && row_of[drawn + 1] <= drawn_rows) ++drawn;
    }
    stepped[0] = drawn;
    surface_seconds += seconds_since(t);
    t = std::chrono::steady_clock::now();
    // What the sliding rows keep: the solve's reach before the next rows it
    // solves, the rows the correction and the measure still read.
    const int keep = std::max(0, std::min({solved - solve_reach, finished - 1, checked - 2}));
    for (int k = 0; k <= K; ++k) {
      if (stepped[k] > residual_done[k]) {
        const int a = residual_done[k], b = stepped[k];
        acquisition.apply(window, window_origin, a, b, acquired);
        int top = 0;
        const float* const src_rows = input.rows(a, b, top).pixels.data() + row_size * (a - top);
        if (k == K) last_residual.make_room(b, keep);
        else step_values[k].make_room(b, std::max(0, stepped[k + 1] - 2 * mesh_reach));
        std::vector<double> row_max(b - a, 0.0);
        double* const last = k == K ? last_residual.row(a) : nullptr;
        float* const next_step = k < K ? step_values[k].row(a) : nullptr;
        tbb::parallel_for(a, b, [&](int y) {
          const std::size_t first = row_size * (y - a);
          for (std::size_t i = first; i < first + row_size; ++i) {
            const double r = double(src_rows[i]) - acquired[i];
            row_max[y - a] = std::max(row_max[y - a], std::abs(r));
            if (k < K) next_step[i] = static_cast<float>(r);
            else last[i] = r;
          }
        });
        if (k == 0) local.residual_before = std::max(local.residual_before, max_abs(row_max));
        residual_done[k] = b;
      }
      if (k == K) break;
      const int ready = residual_done[k] == H ? H : std::max(stepped[k + 1], residual_done[k] - mesh_reach);
      if (ready > stepped[k + 1]) {
        const int first = row_of[stepped[k + 1]];
        const SlidingRows<float>& rows = step_values[k];
        // The rows written: reading another is an error, not a stale value
        // (kept whole, from row 0, for a mesh without triangles or with a
        // hull not convex).
        meshes.add(window, first - window_origin, first, row_of[ready], rows.values, index_t(rows.origin) * W,
                   slide ? index_t(residual_done[k]) * W : index_t(H) * W);
        stepped[k + 1] = ready;
      }
    }
    if (!meshes_done) meshes.release(row_of[stepped[K]]);
    if (!meshes_done && stepped[K] == H) {  // the meshes are read no more
      meshes_done = true;
      local.mesh_steps = K;
      std::vector<SlidingRows<float>>().swap(step_values);
      std::vector<float>().swap(gradient_rows.values);
      if (options.mesh_done) options.mesh_done();
    }
    const int solvable = residual_done[K] == H ? H : std::max(solved, residual_done[K] - solve_reach);
    if (solvable > solved) {
      // To the end of the canonical block that holds the last solvable row:
      // its window's residual is here too (the block ends within
      // block_rows - 1 rows, its window window_rows later), and a block is
      // then solved once, not again for each step of rows that cuts it.
      const int B = grid.block_rows();
      const int through = solvable == H ? H : std::min(H, (solvable + B - 1) / B * B);
      const int first = std::max(0, solved - solve_reach), end = std::min(H, solvable + solve_reach);
      grid.solve_rows(last_residual.rows(first, end), solved_rows, C, first, end, solved, through);
      delta.make_room(through, keep);
      std::copy(solved_rows.begin(), solved_rows.end(), delta.row(solved));
      solved = through;
    }
    // The solve's residual, max |r - G delta|, on the rows whose delta
    // rows within two are solved.
    const int checkable = solved == H ? H : std::max(checked, solved - 2);
    if (checkable > checked) {
      const int first = std::max(0, checked - 2), end = std::min(H, checkable + 2);
      grid.acquire(delta.rows(first, end), acquired_delta, C, first, end);
      const double* r = last_residual.row(checked);
      const double* g = acquired_delta.data() + row_size * (checked - first);
      for (std::size_t i = 0; i < row_size * (checkable - checked); ++i) {
        local.residual_mesh = std::max(local.residual_mesh, std::abs(r[i]));
        local.residual_after = std::max(local.residual_after, std::abs(r[i] - g[i]));
      }
      checked = checkable;
    }
    solve_seconds += seconds_since(t);
    t = std::chrono::steady_clock::now();
    const int finishable = solved == H ? H : std::max(finished, solved - 1);
    if (finishable > finished) {
      // The last steps as make_consistent's, on the window's rows; they
      // read the input's 5x5 around each footprint.
      int top = 0;
      const Image& src = input.rows(std::max(0, finished - 2), std::min(H, finishable + 2), top);
      const RowBand band{top, H, window_origin, out_height};
      grid.add_to(window, delta.values, row_of[finished], row_of[finishable], window_origin, delta.origin);
      if (options.step_edges)
        local.step_edge_footprints += StepEdgeRenderer(src, statistics, band).render(window, finished, finishable);
      if (options.limit_halos)
        local.halo_footprints += HaloLimiter(src, statistics, band).limit(window, finished, finishable);
      for (int first = row_of[finished]; first < row_of[finishable]; first += band_out_rows)
        hand_out(window, window_origin, first, std::min(row_of[finishable], first + band_out_rows), options);
      finished = finishable;
      input.release(std::min(finished - 2, meshes.first_input_row()));
      if (options.progress) options.progress->set(finished);
    }
    finish_seconds += seconds_since(t);
  }
  local.seconds_surface = surface_seconds;
  local.seconds_solve = solve_seconds;
  local.seconds_render = finish_seconds;
  if (stats) *stats = local;
}

int triangle_rows(const Mesh2& mesh, int first, int end) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, mesh.tri.size() / 3, 1 << 16), 0,
      [&](const tbb::blocked_range<std::size_t>& range, int span) {
        for (std::size_t t = 3 * range.begin(); t < 3 * range.end(); t += 3) {
          const double y0 = mesh.points[mesh.tri[t]].y, y1 = mesh.points[mesh.tri[t + 1]].y,
                       y2 = mesh.points[mesh.tri[t + 2]].y;
          const double lo = std::min({y0, y1, y2}), hi = std::max({y0, y1, y2});
          if (hi >= first && lo <= end) span = std::max(span, static_cast<int>(std::ceil(hi - lo)));
        }
        return span;
      },
      [](int a, int b) { return std::max(a, b); });
}

int triangle_rows(const Mesh2& mesh) {
  return triangle_rows(mesh, std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
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
