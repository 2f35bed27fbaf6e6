#include "pipeline/upscale.hpp"

#include "consistency/consistent_reconstruction.hpp"
#include "consistency/input_statistics.hpp"
#include "core/costs.hpp"
#include "image/cubic_surface.hpp"
#include "util/error.hpp"
#include "io/image_io.hpp"
#include "image/image_mesh.hpp"
#include "pipeline/banded_meshes.hpp"
#include "pipeline/banded_upscale.hpp"
#include "pipeline/drive_channels.hpp"
#include "pipeline/stages.hpp"
#include "image/optimizer_choice.hpp"
#include "image/optimizer.hpp"
#include "image/rasterizer.hpp"
#include "util/prefaulted_image.hpp"
#include "util/size_limits.hpp"
#include "util/timing.hpp"
#include "image/triangulation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <future>
#include <cstdio>
#include <limits>
#include <optional>

namespace ddt {
namespace {

// grid_gradients of rows [first, end) (default: all) in parallel: bands of
// rows with a halo of two rows (the reach of its stencils), so every value
// is the one the whole image gives.
std::vector<float> gradients_of(const Image& img, SlopeLimiter limiter, int first = 0, int end = -1) {
  constexpr int band = 64, halo = 2;
  if (end < 0) end = img.height;
  if (first == 0 && end == img.height && img.height <= 2 * band) return grid_gradients(img, limiter);
  const std::size_t row_floats = static_cast<std::size_t>(img.width) * img.channels;
  std::vector<float> g(2 * row_floats * (end - first));
  tbb::parallel_for(0, (end - first + band - 1) / band, [&](int b) {
    const int y0 = first + b * band, y1 = std::min(end, y0 + band);
    const int top = std::max(0, y0 - halo), bottom = std::min(img.height, y1 + halo);
    Image part(img.width, bottom - top, img.channels);
    std::copy(img.pixels.begin() + static_cast<std::ptrdiff_t>(row_floats * top),
              img.pixels.begin() + static_cast<std::ptrdiff_t>(row_floats * bottom), part.pixels.begin());
    const std::vector<float> pg = grid_gradients(part, limiter);
    std::copy(pg.begin() + static_cast<std::ptrdiff_t>(2 * row_floats * (y0 - top)),
              pg.begin() + static_cast<std::ptrdiff_t>(2 * row_floats * (y1 - top)),
              g.begin() + static_cast<std::ptrdiff_t>(2 * row_floats * (y0 - first)));
  });
  return g;
}

// The first output row whose sample lies at or below input row y (its
// centre y + 0.5 sits at output (y + 0.5) * sy - 0.5; rows of a band are the
// output rows sampled between its first and its last input row).
int first_output_row(int y, int in_height, int out_height) {
  if (y <= 0) return 0;
  if (y >= in_height) return out_height;
  const double sy = static_cast<double>(out_height) / in_height;
  return std::clamp(static_cast<int>(std::ceil(y * sy - 0.5)), 0, out_height);
}

// Output rows per band handed to UpscaleOptions::output_rows: about 8 MB
// of floats, which keeps fewer pages in flight and starts the encoder
// sooner than larger bands (docs/performance.md, "Band size"). Where each
// band is rendered on its own (the point model), a RenderPlan keeps a
// band's cost to its rows.
int streamed_band_rows(int out_width, int channels, const UpscaleOptions& options) {
  if (options.output_band_rows > 0) return options.output_band_rows;
  const double row_bytes = 4.0 * out_width * channels;
  return std::clamp(static_cast<int>(8e6 / row_bytes), 16, 4096);
}

struct Band {
  int top, bottom;      // input rows of the band, margins included
  int out_first, out_end;  // output rows it renders
  int out_origin = 0;   // the output row held by row 0 of the image rendered into
};

// The mesh stage of a band: the Delaunay triangulation of its pixel
// centres, then the optimizer on its drive values (`values`: the band's
// samples, W pixels a row). The mesh upscale() renders, and the one
// upscale_mesh() returns. Adds to `local`'s triangles and seconds.
Mesh2 band_mesh(const std::vector<float>& values, int W, int C, const Band& band, const UpscaleOptions& options,
                const CostFunction& cost, const DriveChannels& drive, long long region_triangles, int region_rows,
                const StageRunner& stages, UpscaleStats& local, LawsonStats& ls) {
  const std::size_t n = static_cast<std::size_t>(W) * (band.bottom - band.top);
  auto t0 = Clock::now();
  stages.begin("triangulate");
  Mesh2 mesh;
  {
    std::vector<Point2> points = prefaulted_zeros<Point2>(n);
    tbb::parallel_for(band.top, band.bottom, [&](int y) {
      for (int x = 0; x < W; ++x) points[static_cast<std::size_t>(y - band.top) * W + x] = {x + 0.5, y + 0.5};
    });
    mesh = delaunay_triangulation(std::move(points));
  }
  const double seconds_triangulate = seconds_since(t0);
  local.seconds_triangulate += seconds_triangulate;
  local.triangles += mesh.triangle_count();
  stages.log("triangulate: " + std::to_string(mesh.points.size()) + " points, " +
             std::to_string(mesh.triangle_count()) + " triangles, " + std::to_string(seconds_triangulate) + " s");

  t0 = Clock::now();
  if (options.optimize && mesh.triangle_count() > 0) {
    std::vector<float> own_drive;
    if (!drive.identity) own_drive = drive_values(values.data(), n, C, drive);
    const std::vector<float>& drive_vals = drive.identity ? values : own_drive;
    LawsonOptions lawson = lawson_options<LawsonOptions>(options);
    lawson.region_triangles = region_triangles;
    if (region_rows > 0)  // boundaries on absolute rows that are multiples of region_rows
      lawson.region_origin = static_cast<long long>((region_rows - band.top % region_rows) % region_rows) * 2 * (W - 1);
    if (stages.logging())
      lawson.on_iteration = [&](int iteration, long long flips, double total) {
        char line[160];
        std::snprintf(line, sizeof line, "optimize: %s %d, %lld flips, cost %.9g",
                      region_triangles > 0 ? "phase" : "iteration", iteration, flips, total);
        stages.log(line);
      };
    if (Progress* progress = stages.progress()) {
      // Expected tests: about twice the interior edges, 3 per triangle
      // (3.0 measured on photographs; a little more, so the bar ends full).
      stages.begin("optimize", 3LL * mesh.triangle_count() + mesh.triangle_count() / 8);
      lawson.on_tests = [progress](long long tests) { progress->set(tests); };
    }
    ls = run_optimizer(mesh, drive_vals, drive.K, cost, options.optimizer, options.anneal, lawson, stages.logger());
  }
  const double seconds_optimize = seconds_since(t0);
  local.seconds_optimize += seconds_optimize;
  if (options.optimize) {
    char line[240];
    std::snprintf(line, sizeof line,
                  "optimize: cost %s, %d %s, %d regions, %lld tests, %lld flips, cost %.9g -> %.9g, %.3f s", cost.name,
                  ls.iterations, region_triangles > 0 ? "phases" : "iterations", ls.regions, ls.tests, ls.flips,
                  ls.cost_before, ls.cost_after, seconds_optimize);
    stages.log(line);
  }
  return mesh;
}

// Input rows a band of the whole image's wavefront draws from its own mesh
// (BandedMeshes), or 0 for one mesh: under the region schedule, where a
// band and its margins (what the wavefront holds at once) are at most half
// the image's rows, or as options.mesh_band_rows says.
int wavefront_band_rows(int height, int region_rows, int margin, const UpscaleOptions& options) {
  if (options.mesh_band_rows < 0 || region_rows <= 0 || options.optimizer != Optimizer::lawson) return 0;
  if (options.mesh_band_rows > 0) return options.mesh_band_rows < height ? options.mesh_band_rows : 0;
  // Taller bands redo less margin: at 8 margins a band, a quarter more of
  // the mesh's work (docs/performance.md).
  const int rows = std::max(1024, 8 * margin);
  return 2 * (rows + 2 * margin) <= height ? rows : 0;
}

// The margin a mesh band starts with: two regions and the planned
// triangle height (BandedMeshes widens it where a band needs more).
int planned_mesh_band_margin(int region_rows) { return 2 * region_rows + 8 + planned_triangle_rows + 1; }

// Triangulates, optimizes and renders one band of input rows into `out`.
// Returns the optimizer's statistics (phases in `iterations`).
// `input` holds rows [src_top, src_top + input.height()) of an image of
// image_height rows; the band lies within them. An input read by rows
// (not held whole) takes only the whole image's wavefront from meshes made
// by bands, with the whole input's `statistics`.
LawsonStats run_band(InputRows& input, int src_top, int image_height, const Band& band, int out_width, int out_height,
                     const UpscaleOptions& options, const CostFunction& cost, const DriveChannels& drive,
                     long long region_triangles, int region_rows,
                     const std::function<Image&()>& output, UpscaleStats& local,
                     int margin = std::numeric_limits<int>::max(), const InputStatistics* statistics = nullptr,
                     int* margin_needed = nullptr) {
  const StageRunner stages(options.log, options.progress);
  const int W = input.width(), C = input.channels();
  const Image* src = input.whole();
  // The whole image, all its output rows (a tile whose margins reach both
  // borders is still a band: it renders only its own rows).
  const bool whole = band.top == 0 && band.bottom == image_height && band.out_first == 0 && band.out_end == out_height;

  // The band's samples (the image itself when the band is the image).
  std::vector<float> band_pixels;
  if (!whole && src)
    band_pixels.assign(
        src->pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(band.top - src_top) * W * C),
        src->pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(band.bottom - src_top) * W * C));
  const std::vector<float>& values = whole && src ? src->pixels : band_pixels;

  const bool consistent = options.model.kind != AcquisitionModel::Kind::point;
  // The whole image's consistent reconstruction, streamed, draws its
  // surface a band of rows at a time as its wavefront needs it, and holds
  // no whole output (make_consistent_streamed); on a tall image, from
  // meshes made a band at a time too.
  const bool wavefront = consistent && whole && options.output_rows &&
                         make_consistent_streams(options.model, W, image_height, out_width, out_height);
  const int mesh_band_rows = wavefront ? wavefront_mesh_band_rows(W, image_height, out_width, out_height, options) : 0;
  if (!src && mesh_band_rows == 0)
    throw Error("an input read by rows takes the streamed reconstruction from meshes made by bands only");
  LawsonStats ls;
  Mesh2 mesh;
  if (mesh_band_rows == 0)
    mesh = band_mesh(values, W, C, band, options, cost, drive, region_triangles, region_rows, stages, local, ls);
  // A margin too narrow for the phases run (and for the consistent
  // reconstruction's reach on this mesh): the caller redoes the band with
  // a wider one, so nothing is drawn (or handed out) from this one.
  if (!whole) {
    const int needed = (options.optimize ? band_margin_needed(ls.iterations, region_rows) : 0) +
                       (consistent ? consistency_margin_needed(triangle_rows(mesh), options.model, W, image_height,
                                                               out_width, out_height)
                                   : 0);
    if (margin_needed) *margin_needed = needed;
    if (needed > margin) return ls;
  }

  // The image drawn into (the whole output, or the band's rows), once it
  // is allocated; unused when the rows are streamed. A band of the
  // consistent reconstruction draws all its rows, margins too, into an
  // image of its own, and keeps its inner rows once corrected.
  const bool band_image = consistent && !whole;
  Image own_rows;
  if (band_image) {
    own_rows = Image(out_width,
                     first_output_row(band.bottom, image_height, out_height) -
                         first_output_row(band.top, image_height, out_height),
                     C);
  }
  Image no_output;
  Image& out = band_image ? own_rows : wavefront ? no_output : output();
  auto t0 = Clock::now();
  RenderGrid grid;
  grid.width = out_width;
  grid.height = out_height;
  grid.scale_x = static_cast<double>(out_width) / W;
  grid.scale_y = static_cast<double>(out_height) / image_height;
  grid.first_row = band_image ? first_output_row(band.top, image_height, out_height) : band.out_first;
  grid.rows = band_image ? own_rows.height : band.out_end - band.out_first;
  RenderStats rs;
  std::vector<float> gradients;
  const bool cubic = options.render == Render::cubic;
  if (cubic && !wavefront) {  // the wavefront makes them a band of rows at a time
    if (whole) {
      gradients = gradients_of(*src, options.slopes);
    } else {
      Image part(W, band.bottom - band.top, C);
      part.pixels = values;
      gradients = gradients_of(part, options.slopes);
    }
  }
  const std::vector<float>* patch_gradients = cubic ? &gradients : nullptr;
  std::optional<RenderPlan> plan;
  if (!wavefront) plan.emplace(mesh, grid);
  // Rows [first, end) of the grid into `into` from its row `at`, with the
  // bits of the whole image's render: where a group of rows is cut, drawn
  // from the whole groups around them (RenderPlan::window_boundary).
  auto draw_rows = [&](Image& into, int at, int first, int end, Progress* progress) {
    const int a = plan->window_start(first), b = plan->window_boundary(end);
    if (a == first && b == end)
      return render_mesh_into(into, at, *plan, values, C, first, end - first, &rs, patch_gradients, progress);
    Image groups(out_width, b - a, C);
    render_mesh_into(groups, 0, *plan, values, C, a, b - a, &rs, patch_gradients, progress);
    const std::ptrdiff_t row_floats = static_cast<std::ptrdiff_t>(out_width) * C;
    std::copy(groups.pixels.begin() + row_floats * (first - a), groups.pixels.begin() + row_floats * (end - a),
              into.pixels.begin() + row_floats * at);
  };
  if (options.output_rows && !consistent) {
    // Streamed: the band's output rows rendered and handed out a part at a
    // time, cut where the render keeps its bits.
    const int step = streamed_band_rows(out_width, C, options);
    for (int first = band.out_first; first < band.out_end;) {
      const int end = std::min(band.out_end, std::max(first + 1, plan->window_boundary(first + step)));
      Image part(out_width, end - first, C);
      draw_rows(part, 0, first, end, stages.progress());
      options.output_rows(std::move(part), first);
      first = end;
    }
  } else if (band_image) {
    // A band of the consistent reconstruction keeps only rows far from its
    // ends (its margins), where any cut keeps the bits.
    render_mesh_into(out, 0, *plan, values, C, grid.first_row, grid.rows, &rs, patch_gradients, stages.progress());
  } else if (!wavefront) {
    draw_rows(out, band.out_first - band.out_origin, grid.first_row, grid.first_row + grid.rows, stages.progress());
  }
  auto log_render = [&](double seconds, const char* how) {
    stages.log("render: " + std::to_string(out_width) + "x" + std::to_string(band.out_end - band.out_first) + ", " +
               std::to_string(rs.triangles) + " + " + std::to_string(rs.rim_triangles) + " rim triangles, " +
               std::to_string(seconds) + " s" + how);
  };
  if (!wavefront) {
    const double seconds_render = seconds_since(t0);
    local.seconds_render += seconds_render;
    log_render(seconds_render, "");
  }
  if (!consistent) return ls;
  t0 = Clock::now();
  stages.begin("consistency");
  ConsistencyOptions co;
  co.model = options.model;
  co.step_edges = options.step_edges;
  if (!band_image) co.output_rows = options.output_rows;
  co.output_band_rows = streamed_band_rows(out_width, C, options);
  ConsistencyStats cs;
  if (wavefront) {
    co.progress = stages.progress();
    // The mesh is freed once the last mesh step is drawn (the wavefront
    // frees its own rows of gradients).
    co.mesh_done = [&] { mesh = Mesh2(); };
    GradientRows gradient_rows;
    if (cubic)
      gradient_rows = [&](int first, int end) {  // from the input's rows their stencils reach
        int top = 0;
        const Image& rows = input.rows(std::max(0, first - 2), std::min(image_height, end + 2), top);
        return gradients_of(rows, options.slopes, first - top, end - top);
      };
    double mesh_seconds = 0;  // the bands' meshes, made within the wavefront's surface stage
    if (mesh_band_rows > 0) {
      const StageRunner quiet(nullptr, nullptr);
      int made = 0;
      auto make = [&](int top, int bottom, const std::vector<float>& rows) {
        const auto t = Clock::now();
        LawsonStats band_ls;
        BandMesh made_band;
        made_band.mesh = band_mesh(rows, W, C, Band{top, bottom, 0, 0}, options, cost, drive, region_triangles,
                                   region_rows, quiet, local, band_ls);
        made_band.phases = band_ls.iterations;
        ls.iterations = std::max(ls.iterations, band_ls.iterations);
        ls.regions = std::max(ls.regions, band_ls.regions);
        ls.flips += band_ls.flips;
        ls.tests += band_ls.tests;
        ls.cost_before += band_ls.cost_before;
        ls.cost_after += band_ls.cost_after;
        const double seconds = seconds_since(t);
        mesh_seconds += seconds;
        char line[200];
        std::snprintf(line, sizeof line, "mesh band %d: rows %d..%d, %d triangles, %d phases, %lld flips, %.3f s",
                      ++made, top, bottom, made_band.mesh.triangle_count(), band_ls.iterations, band_ls.flips,
                      seconds);
        stages.log(line);
        return made_band;
      };
      co.statistics = statistics;
      BandedMeshes meshes(input, grid, mesh_band_rows, region_rows, planned_mesh_band_margin(region_rows), make);
      make_consistent_streamed(out_width, out_height, meshes, gradient_rows, input, co, &cs, &rs);
      stages.log("mesh bands: " + std::to_string(meshes.bands_made()) + " of " + std::to_string(mesh_band_rows) +
                 " rows, margin " + std::to_string(meshes.margin()) + " rows, " +
                 std::to_string(meshes.bands_redone()) + " redone with a wider margin, at most " +
                 std::to_string(meshes.most_held()) + " held at once");
    } else {
      make_consistent_streamed(out_width, out_height, values, gradient_rows, mesh, *src, co, &cs, &rs);
    }
    local.seconds_render += cs.seconds_surface - mesh_seconds;
    log_render(cs.seconds_surface - mesh_seconds, " (a band at a time, with the consistent reconstruction)");
  } else {
    // The mesh and the gradients are freed before the last steps, whose
    // bands of output rows can then reuse their memory.
    plan.reset();
    std::vector<float>().swap(gradients);
    co.mesh_done = [&mesh] { mesh = Mesh2(); };
    if (band_image) {
      Image rows(W, band.bottom - band.top, C);
      rows.pixels = values;
      co.band = RowBand{band.top, image_height, grid.first_row, out_height};
      co.statistics = statistics;
      make_consistent(out, mesh, rows, co, &cs);
      // The band's own rows, into the whole output or handed out.
      const std::ptrdiff_t row_floats = static_cast<std::ptrdiff_t>(out_width) * C;
      const auto kept = own_rows.pixels.begin() + row_floats * (band.out_first - grid.first_row);
      if (options.output_rows) {
        const int step = streamed_band_rows(out_width, C, options);
        for (int first = band.out_first; first < band.out_end; first += step) {
          const int end = std::min(band.out_end, first + step);
          Image part(out_width, end - first, C);
          std::copy(kept + row_floats * (first - band.out_first), kept + row_floats * (end - band.out_first),
                    part.pixels.begin());
          options.output_rows(std::move(part), first);
        }
      } else {
        Image& whole_out = output();
        std::copy(kept, kept + row_floats * (band.out_end - band.out_first),
                  whole_out.pixels.begin() + row_floats * (band.out_first - band.out_origin));
      }
    } else {
      make_consistent(out, mesh, *src, co, &cs);
    }
  }
  local.consistency_mesh_steps = cs.mesh_steps;
  local.consistency_residual = cs.residual_after;
  local.seconds_consistency = seconds_since(t0) - cs.seconds_surface;
  char line[360];
  std::snprintf(line, sizeof line,
                "consistency (%s): residual %.3g, %.3g after %d steps on the mesh, %.3g after the grid solve; "
                "%lld step-edge footprints, %lld halo-limited; operators %.3f s, solve %.3f s, %s %.3f s%s",
                to_string(options.model).c_str(), cs.residual_before, cs.residual_mesh, cs.mesh_steps,
                cs.residual_after, cs.step_edge_footprints, cs.halo_footprints, cs.seconds_operator, cs.seconds_solve,
                wavefront ? "last steps" : "render", cs.seconds_render,
                wavefront ? ("; a wavefront down the rows, " + std::to_string(cs.held_rows) + " output rows held").c_str()
                          : "");
  stages.log(line);
  return ls;
}

// Triangles of a region of the optimizer on an image `width` pixels wide:
// whole rows of cells, so that tiles (bands of rows) cut the same regions
// as the whole image; -1 where the image is one region.
long long region_triangles_of(int width, int region_rows) {
  return region_rows > 0 ? region_rows * 2LL * std::max(1, width - 1) : -1;
}

// The bytes a job may plan for: options.max_memory, else half the machine's.
double job_budget(const UpscaleOptions& options) {
  return options.max_memory > 0 ? double(options.max_memory) : 0.5 * double(physical_memory());
}

// The checks before any work: the cost's name and the annealing schedule.
const CostFunction& checked_cost(const UpscaleOptions& options) {
  const CostFunction& cost = find_cost(options.cost);
  check_optimizer(options.optimizer, options.anneal);
  return cost;
}

// The optimizer's statistics of a run over one band (the whole image).
void take_optimizer_stats(const LawsonStats& ls, UpscaleStats& stats) {
  stats.take(ls);
  stats.tests = ls.tests;
  stats.regions = ls.regions;
}

}  // namespace

Image upscale(const Image& src, int out_width, int out_height, const UpscaleOptions& options, UpscaleStats* stats) {
  if (src.empty() || src.width <= 0 || src.height <= 0) throw Error("the input image is empty");
  if (out_width < 1 || out_height < 1) throw Error("the output size must be at least 1x1");
  const CostFunction& cost = checked_cost(options);
  const DriveChannels drive = drive_channels(src, options);
  UpscaleStats local;
  const int W = src.width, H = src.height, C = src.channels;

  const int region_rows = optimizer_region_rows(W, H, options);

  // Tiles: only where the whole image would not fit (or when asked), and
  // only with Lawson (annealing's random moves span the image; the
  // look-ahead's sweeps have no region schedule).
  int tile_rows = 0;
  // An output with fewer pixels than the input on an axis cannot reproduce
  // it: a reduction is the plain interpolation under every model.
  const bool reduced = out_width < W || out_height < H;
  const bool consistent = is_consistent(W, H, out_width, out_height, options.model);
  const bool can_tile = W >= 2 && H >= 2 && options.optimizer == Optimizer::lawson;
  if (can_tile && options.tile_rows > 0) {
    tile_rows = options.tile_rows;
  } else if (can_tile && options.tile_rows == 0) {
    const double budget = job_budget(options);
    const double input = 4.0 * C * W * H;
    // Streamed through the wavefront from meshes made by bands, the whole
    // image holds a band's mesh and the wavefront's rows.
    const int mesh_bands = options.output_rows ? wavefront_mesh_band_rows(W, H, out_width, out_height, options) : 0;
    const double whole_job = mesh_bands > 0 ? wavefront_mesh_bytes(W, H, C, out_width, out_height, mesh_bands, options)
                                            : banded_bytes(W, H, C, out_width, out_height, H, 0);
    if (input + whole_job > budget) {
      // The bands beside the input and the output held whole (unless streamed).
      const double held_output = options.output_rows ? 0.0 : 4.0 * C * out_width * out_height;
      tile_rows =
          std::min((H + 1) / 2, banded_rows(W, H, C, out_width, out_height, options, budget - input - held_output));
    }
  }
  // Bands reproduce the whole image's result only under the region
  // schedule; an image small enough for one region never needs them.
  if (tile_rows >= H || region_rows <= 0) tile_rows = 0;
  // The consistent reconstruction solves over the whole image; in tiles the
  // image gets the point model's interpolation, and the caller is told.
  UpscaleOptions band_options = options;
  if (reduced && options.model.kind != AcquisitionModel::Kind::point) {
    band_options.model.kind = AcquisitionModel::Kind::point;
    if (options.log) options.log("consistency: skipped, the output is smaller than the input on an axis (point model)");
  }
  const long long region_triangles = region_triangles_of(W, region_rows);
  // Streamed, every tile hands its rows out itself; the untiled consistent
  // reconstruction holds the whole output and hands out each band of it
  // once its last steps are done (make_consistent).
  const bool streamed = static_cast<bool>(options.output_rows);
  const bool whole_output =
      !streamed || (consistent && tile_rows == 0 && !make_consistent_streams(options.model, W, H, out_width, out_height));
  // The output's pages are mapped while the mesh is built.
  Image out;
  std::future<Image> allocating = whole_output ? prefaulted_image_async(out_width, out_height, C) : std::future<Image>();
  const std::function<Image&()> output = [&]() -> Image& {
    if (allocating.valid()) out = allocating.get();
    return out;
  };
  if (tile_rows == 0) {
    InputRows input(src);
    const LawsonStats ls = run_band(input, 0, H, Band{0, H, 0, out_height}, out_width, out_height, band_options, cost,
                                    drive, region_triangles, region_rows, output, local);
    take_optimizer_stats(ls, local);
    // Streamed, the consistent reconstruction has handed its rows out.
    if (streamed) out = Image();
  } else {
    // Tiles are the banded reader's bands, read from memory: each band's
    // rows into the whole output, or handed out (banded_upscale.hpp).
    const RowSource source{W, H, C, [&src](int first, int end, float* rows) {
                             std::copy(src.pixels.begin() + static_cast<std::ptrdiff_t>(src.index(0, first)),
                                       src.pixels.begin() + static_cast<std::ptrdiff_t>(src.index(0, end)), rows);
                           }};
    UpscaleOptions tile_options = band_options;
    if (!streamed)
      tile_options.output_rows = [&output](Image rows, int first_row) {
        Image& whole = output();
        std::copy(rows.pixels.begin(), rows.pixels.end(),
                  whole.pixels.begin() + static_cast<std::ptrdiff_t>(whole.index(0, first_row)));
      };
    local = upscale_banded(source, out_width, out_height, tile_options, tile_rows);
  }
  if (stats) *stats = local;
  output();  // the allocation is waited for even where no band drew into it
  return out;
}

bool upscale_reads_by_rows(int width, int height, int channels, int out_width, int out_height,
                           const UpscaleOptions& options) {
  if (width < 2 || height < 2 || options.tile_rows > 0) return false;
  const int mesh_bands = wavefront_mesh_band_rows(width, height, out_width, out_height, options);
  if (mesh_bands == 0) return false;
  // Where even that would not fit, upscale() cuts the image into tiles.
  const double bytes = wavefront_mesh_bytes(width, height, channels, out_width, out_height, mesh_bands, options);
  return bytes <= job_budget(options);
}

UpscaleStats upscale_by_rows(const RowSource& source, int out_width, int out_height, const UpscaleOptions& options) {
  const int W = source.width, H = source.height, C = source.channels;
  if (W <= 0 || H <= 0 || C <= 0) throw Error("the input image is empty");
  if (!options.output_rows) throw Error("an input read by rows needs its output streamed (options.output_rows)");
  if (!upscale_reads_by_rows(W, H, C, out_width, out_height, options))
    throw Error("this enlargement does not read its input by rows (upscale_reads_by_rows)");
  const CostFunction& cost = checked_cost(options);
  const DriveChannels drive = drive_channels(C, options);
  const int region_rows = optimizer_region_rows(W, H, options);
  const long long region_triangles = region_triangles_of(W, region_rows);
  const InputStatistics statistics = input_statistics(source, options.progress);
  InputRows input(source);
  UpscaleStats local;
  Image unused;
  const LawsonStats ls = run_band(input, 0, H, Band{0, H, 0, out_height}, out_width, out_height, options, cost, drive,
                                  region_triangles, region_rows, [&]() -> Image& { return unused; }, local,
                                  std::numeric_limits<int>::max(), &statistics);
  take_optimizer_stats(ls, local);
  if (options.log)
    options.log("input: read by rows, at most " + std::to_string(input.peak_rows()) + " of " + std::to_string(H) +
                " held, " + std::to_string(input.rows_read_again()) + " read again");
  return local;
}

Mesh2 upscale_mesh(const Image& src, const UpscaleOptions& options, UpscaleStats* stats) {
  if (src.empty() || src.width <= 0 || src.height <= 0) throw Error("the input image is empty");
  const CostFunction& cost = checked_cost(options);
  const DriveChannels drive = drive_channels(src, options);
  const int region_rows = optimizer_region_rows(src.width, src.height, options);
  const long long region_triangles = region_triangles_of(src.width, region_rows);
  UpscaleStats local;
  LawsonStats ls;
  Mesh2 mesh = band_mesh(src.pixels, src.width, src.channels, Band{0, src.height, 0, 0}, options, cost, drive,
                         region_triangles, region_rows, StageRunner(options.log, options.progress), local, ls);
  take_optimizer_stats(ls, local);
  if (stats) *stats = local;
  return mesh;
}

void add_band_stats(UpscaleStats& total, const UpscaleStats& band, bool first_band) {
  total += static_cast<const StageSeconds&>(band);
  total.triangles += band.triangles;
  total.iterations = std::max(total.iterations, band.iterations);
  total.flips += band.flips;
  total.tests += band.tests;
  if (first_band) total.regions = band.regions;
  total.cost_before += band.cost_before;
  total.cost_after += band.cost_after;
}

int output_row_of(int y, int in_height, int out_height) { return first_output_row(y, in_height, out_height); }

int wavefront_mesh_band_rows(int width, int height, int out_width, int out_height, const UpscaleOptions& options) {
  if (!is_consistent(width, height, out_width, out_height, options.model) ||
      !make_consistent_streams(options.model, width, height, out_width, out_height))
    return 0;
  const int region_rows = optimizer_region_rows(width, height, options);
  return wavefront_band_rows(height, region_rows, planned_mesh_band_margin(region_rows), options);
}

double wavefront_mesh_bytes(int width, int height, int channels, int out_width, int out_height, int band_rows,
                            const UpscaleOptions& options) {
  const int margin = planned_mesh_band_margin(optimizer_region_rows(width, height, options));
  // One band with its margins and the rows it takes over from the band
  // before (BandedMeshes), its input rows read by rows.
  const double band_pixels =
      double(width) * std::min<double>(height, band_rows + 2.0 * margin + 4.0 * (planned_triangle_rows + 2));
  const double wavefront_rows = std::min<double>(out_height, 256.0 * out_height / height);
  return (110.0 + 6.0 * channels) * band_pixels + 3 * 4.0 * channels * out_width * wavefront_rows;
}

int band_margin_needed(int phases, int region_rows) { return (phases + 1) * ((region_rows + 1) / 2) + 8; }

int planned_band_margin(int region_rows, bool consistent, const AcquisitionModel& model, int width, int height,
                        int out_width, int out_height) {
  return 2 * region_rows + 8 +
         (consistent ? consistency_margin_needed(planned_triangle_rows, model, width, height, out_width, out_height)
                     : 0);
}

bool is_consistent(int width, int height, int out_width, int out_height, const AcquisitionModel& model) {
  return model.kind != AcquisitionModel::Kind::point && out_width >= width && out_height >= height;
}

int widened_band_margin(int margin, int needed, int region_rows) {
  return std::max(margin + region_rows, needed + region_rows);
}

Image upscale_rows(const Image& rows, int top, int image_height, int first, int end, int out_width, int out_height,
                   const UpscaleOptions& options, UpscaleStats* stats, const InputStatistics* statistics,
                   int* margin_needed) {
  if (rows.empty() || rows.width <= 0 || rows.height <= 0) throw Error("the input image is empty");
  if (out_width < 1 || out_height < 1) throw Error("the output size must be at least 1x1");
  const int bottom = top + rows.height;
  if (top < 0 || bottom > image_height || first < top || end > bottom || first >= end)
    throw Error("upscale_rows: rows " + std::to_string(first) + ".." + std::to_string(end) + " are not within the " +
                "given rows " + std::to_string(top) + ".." + std::to_string(bottom) + " of an image of " +
                std::to_string(image_height));
  const bool whole = top == 0 && bottom == image_height;
  const bool consistent = is_consistent(rows.width, image_height, out_width, out_height, options.model);
  if (!whole && consistent && !statistics)
    throw Error("upscale_rows: a band of the consistent reconstruction needs the whole input's statistics");
  const CostFunction& cost = checked_cost(options);
  const DriveChannels drive = drive_channels(rows, options);
  const int region_rows = optimizer_region_rows(rows.width, image_height, options);
  if (!whole && options.optimize && (region_rows <= 0 || options.optimizer != Optimizer::lawson))
    throw Error("a band equals the whole image's rows only under Lawson's region schedule "
                "(optimizer lawson, region_rows > 0)");
  const long long region_triangles = region_triangles_of(rows.width, region_rows);
  Band band{top, bottom, first_output_row(first, image_height, out_height),
            first_output_row(end, image_height, out_height)};
  band.out_origin = band.out_first;
  Image out(out_width, band.out_end - band.out_first, rows.channels);
  UpscaleStats local;
  constexpr int uncut = std::numeric_limits<int>::max();  // a side at the image's border
  const int cut_margin = std::min(top > 0 ? first - top : uncut, bottom < image_height ? bottom - end : uncut);
  local.tile_margin = cut_margin == uncut ? 0 : cut_margin;
  UpscaleOptions band_options = options;
  if (!consistent) band_options.model.kind = AcquisitionModel::Kind::point;
  int needed = 0;
  InputRows input(rows);
  const LawsonStats ls = run_band(input, top, image_height, band, out_width, out_height, band_options, cost, drive,
                                  region_triangles, region_rows, [&]() -> Image& { return out; }, local,
                                  cut_margin, statistics, &needed);
  take_optimizer_stats(ls, local);
  if (margin_needed) *margin_needed = needed;
  if (needed > cut_margin && margin_needed) return Image();
  if (needed > cut_margin)
    throw Error("a margin of " + std::to_string(local.tile_margin) + " rows is too narrow for the " +
                std::to_string(ls.iterations) + " phases of the optimizer" +
                (consistent ? " and the consistent reconstruction" : "") + ": give at least " +
                std::to_string(needed) + " rows");
  if (stats) *stats = local;
  return out;
}

}  // namespace ddt
