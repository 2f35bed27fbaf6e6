#pragma once
// ddt::upscale — enlarge an image by data-dependent triangulation (DDT).
//
// Pipeline: samples at pixel centres -> Delaunay triangulation (CGAL) ->
// generalized Lawson optimization of the weighted-content cost -> scanline
// rendering of the piecewise-linear surface at the output resolution.
//
// Output pixel (X, Y) samples the surface at ((X + 0.5) / sx, (Y + 0.5) / sy)
// with sx = out_width / in_width, sy = out_height / in_height. Outside the
// convex hull of the samples (the half-pixel rim) the value is that of the
// nearest hull point.
//
// Errors: throws ddt::Error (bad options, empty image).

#include "consistency/acquisition_model.hpp"
#include "image/annealing.hpp"
#include "util/image.hpp"
#include "util/progress.hpp"

#include <OpenImageIO/imagebuf.h>

#include <functional>
#include <string>
#include <vector>

namespace ddt {

struct UpscaleOptions {
  std::string cost = "sederberg";   // a name from cost_names() (costs.hpp)
  bool luma_cost = false;           // flips decided on luminance only (else: sum over colour channels)
  int alpha_channel = -1;           // interpolated, never drives flips
  bool optimize = true;             // false: render the initial Delaunay mesh
  double relative_tolerance = 1e-9; // a flip must lower the local cost by more than this fraction
  int max_iterations = 10000;       // safety bound on Lawson sweeps
  std::string optimizer = "lawson"; // "lawson", "anneal" (simulated annealing, then Lawson; annealing.hpp)
                                    // or "lookahead" (Lawson with two-flip moves; lookahead.hpp)
  AnnealOptions anneal;             // the annealing schedule and seed, when optimizer == "anneal"
  // Surface drawn on the mesh: "cubic" (default; cubic Bézier patches from
  // slope-limited vertex gradients, cubic_surface.hpp) or "linear" (the
  // paper's piecewise-linear surface).
  std::string render = "cubic";
  std::string slopes = "mc4";       // slope limiter of the cubic mode: mc4, mc, central, minmod
  // How an input pixel was made (acquisition_model.hpp): box (default), the
  // output's footprint averages reproduce the input (the consistent
  // reconstruction, consistent_reconstruction.hpp); point: the surface
  // interpolates the samples, no correction.
  AcquisitionModel model;
  // Box model: a pixel whose 3x3 neighbourhood one straight edge between
  // two flat levels explains is drawn as that edge (step_edges.hpp).
  bool step_edges = true;
  std::function<void(const std::string&)> log;  // verbose lines; may be empty
  // Speed and memory (docs/performance.md). Regions of the parallel
  // optimizer in rows of input pixels: 0 automatic (optimizer.hpp), < 0
  // one region (the plain sequential order).
  int region_rows = 0;
  // Tiles: bands of tile_rows input rows, full width, with overlapping
  // margins, each triangulated, optimized and rendered on its own; the
  // output is the untiled one, bit for bit. 0: automatic (tiles only when
  // the whole image would need more than max_memory bytes), < 0: never.
  // Only under the region schedule (region_rows > 0, or automatic on
  // images of more than 2 * default_region_triangles triangles). Tiles
  // use the point model (the consistent reconstruction solves over the
  // whole image): UpscaleStats::consistency_skipped says so.
  int tile_rows = 0;
  long long max_memory = 0;         // 0: half the physical memory
  Progress* progress = nullptr;     // stages and work done, for a progress bar; may be null
  // Streaming (io/band_writer.hpp): when set, the output is handed to this
  // in bands of rows, top to bottom, each row once, and upscale() returns
  // an empty image. Under the point model (and in tiles) each band is
  // rendered on its own, so the whole output is never held; the consistent
  // reconstruction renders the whole output, then hands it out in bands.
  // The rows are those of the returned image, bit for bit.
  std::function<void(Image rows, int first_row)> output_rows;
  int output_band_rows = 0;         // rows per band handed out; 0: about 24 MB of floats
};

// The render modes, and a check that throws ddt::Error listing them.
std::vector<std::string> render_names();
void check_render_name(const std::string& name);

struct UpscaleStats {
  int iterations = 0;
  long long flips = 0;
  long long triangles = 0;
  double cost_before = 0, cost_after = 0;
  double seconds_triangulate = 0, seconds_optimize = 0, seconds_render = 0;
  long long tests = 0;   // edge tests of the optimizer
  int regions = 1;       // optimizer regions (of the first tile)
  int tiles = 1;         // bands the image was processed in
  int tile_margin = 0;   // rows of overlap on each side of a tile
  // The consistent reconstruction (model other than point).
  int consistency_mesh_steps = 0;    // back-projection steps on the data-dependent mesh
  double consistency_residual = 0;  // max |input - acquire(output)| at input resolution, before rounding
  double seconds_consistency = 0;
  bool consistency_skipped = false;  // tiled: the point model was used instead
};

// Enlarges `src` to out_width x out_height (each >= 1).
Image upscale(const Image& src, int out_width, int out_height, const UpscaleOptions& options = {},
              UpscaleStats* stats = nullptr);

// One band of the enlargement, for callers that split an image themselves
// (Dask blocks, python/ddtscale/dask.py): output rows
// [output_row_of(first), output_row_of(end)) of upscale(image, out_width,
// out_height, options), computed from input rows [top, top + rows.height)
// of the image (image_height rows in all) that hold [first, end) with
// margins. Equal to those rows of upscale() bit for bit when the band is the
// whole image, or under the point model and Lawson's region schedule
// (options.region_rows > 0, or automatic on a large image) with margins of
// band_margin_needed(phases, region_rows) rows where the band is cut.
// Throws ddt::Error otherwise (too narrow a margin: after the work, with the
// width needed).
Image upscale_rows(const Image& rows, int top, int image_height, int first, int end, int out_width, int out_height,
                   const UpscaleOptions& options = {}, UpscaleStats* stats = nullptr);
// The first output row sampled at or below input row y.
int output_row_of(int y, int in_height, int out_height);
// Rows of margin a band needs on a cut side for `phases` phases of the
// region schedule (docs/performance.md).
int band_margin_needed(int phases, int region_rows);

// Outputs larger than this many pixels are refused by the command line and
// the Python module unless raised (--max-pixels, max_pixels=).
inline constexpr long long default_max_pixels = 1LL << 28;

// OpenImageIO-shaped form: dst is resized to out_width x out_height of
// roi (default: all of src) and filled; returns false and sets dst's error
// on failure.
bool upscale(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, int out_width, int out_height,
             const UpscaleOptions& options = {}, OIIO::ROI roi = {});

}  // namespace ddt
