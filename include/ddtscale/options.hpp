#pragma once
// The choices among the library's options, typed. Each is parsed once
// from its name where a user gives it (the command line, the Python
// module, `ddtscale eval`'s method names) by *_by_name, which throws
// ddt::Error with a one-line message listing the valid names, and named
// back by to_string (for --help defaults, logs and the Python defaults).
// Then the options of an image enlargement (UpscaleOptions), with the
// acquisition model and the annealing schedule they hold.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ddt {

// The mesh optimizer (image/optimizer_choice.hpp): the generalized Lawson
// procedure, simulated annealing then Lawson, or Lawson with two-flip moves.
enum class Optimizer { lawson, anneal, lookahead };

// The surface drawn on the mesh: cubic Bézier patches from slope-limited
// vertex gradients (image/cubic_surface.hpp), or the paper's
// piecewise-linear surface.
enum class Render { cubic, linear };

// The slope limiter of the cubic render's vertex gradients
// (image/cubic_surface.hpp).
enum class SlopeLimiter { central, mc, mc4, minmod };

const std::vector<std::string>& optimizer_names();  // lawson, anneal, lookahead
Optimizer optimizer_by_name(const std::string& name);
const char* to_string(Optimizer optimizer);

const std::vector<std::string>& render_names();  // cubic, linear
Render render_by_name(const std::string& name);
const char* to_string(Render render);

const std::vector<std::string>& slope_limiter_names();  // mc4, mc, central, minmod
SlopeLimiter slope_limiter_by_name(const std::string& name);
const char* to_string(SlopeLimiter limiter);

// How an input pixel was made from the continuous image (the consistent
// reconstruction makes the output reproduce the input under it):
//   point        a sample at its centre: the plain interpolation
//   box          the average over its area (default)
//   gauss:SIGMA  the area average blurred by a Gaussian PSF of SIGMA input pixels
//   bicubic      MATLAB's antialiased imresize, the SR benchmark's
struct AcquisitionModel {
  enum class Kind { point, box, gauss, bicubic };
  Kind kind = Kind::box;
  double sigma = 0;  // gauss: the PSF's standard deviation in input pixels (> 0)
};

// Parses "point", "box", "gauss:SIGMA" (SIGMA > 0 and finite) or "bicubic";
// throws ddt::Error with the accepted forms on anything else.
AcquisitionModel parse_acquisition_model(const std::string& text);
std::string to_string(const AcquisitionModel& model);
std::vector<std::string> acquisition_model_names();  // the forms, for --help

// The schedule of simulated annealing (optimizer anneal; the algorithm and
// its defaults: image/annealing.hpp in the sources).
struct AnnealOptions {
  std::uint64_t seed = 1;
  double initial_temperature = 0;   // <= 0: automatic, from initial_acceptance
  double initial_acceptance = 0.8;  // in (0, 1): probability of accepting a mean uphill flip at T0
  double cooling = 0.9;             // in (0, 1): T <- cooling * T after each temperature step
  int temperature_steps = 50;       // >= 0
  double moves_per_edge = 1;        // >= 0: proposals per interior edge at each temperature
  bool final_lawson = true;         // descend to a local optimum at the end
  // Called after each temperature step with (step, T, flips accepted in
  // it, running total cost).
  std::function<void(int, double, long long, double)> on_step;
};

struct Image;     // an image of float samples (util/image.hpp in the sources)
class Progress;  // the command line's progress bar (util/progress.hpp in the sources)

// Outputs larger than this many pixels are refused by the command line and
// the Python module unless raised (--max-pixels, max_pixels=), and by the
// ImageBuf forms (UpscaleOptions::max_pixels).
inline constexpr long long default_max_pixels = 1LL << 28;

struct UpscaleOptions {
  // The output size of the ImageBuf forms (ddtscale.hpp), by the rules of
  // --scale / --width / --height: a scale > 0, or a width and/or a height
  // (the missing one follows the aspect ratio, rounded); 0: not given. An
  // output of more than max_pixels pixels is refused.
  double scale = 0;
  int width = 0, height = 0;
  long long max_pixels = default_max_pixels;
  // The flip cost: sederberg (default), variance, sederberg-edge, abn, jnd,
  // dlp, dp and their -edge forms (`ddtscale --list-costs`).
  std::string cost = "sederberg";
  bool luma_cost = false;           // flips decided on luminance only (else: sum over colour channels)
  int alpha_channel = -1;           // interpolated, never drives flips (ImageBuf forms: -1 takes the spec's)
  bool optimize = true;             // false: render the initial Delaunay mesh
  double relative_tolerance = 1e-9; // a flip must lower the local cost by more than this fraction
  int max_iterations = 10000;       // safety bound on Lawson sweeps
  // lawson, anneal (simulated annealing, then Lawson) or lookahead
  // (Lawson with two-flip moves).
  Optimizer optimizer = Optimizer::lawson;
  AnnealOptions anneal;             // the annealing schedule and seed, when optimizer is anneal
  // Surface drawn on the mesh: cubic (default; cubic Bézier patches from
  // slope-limited vertex gradients) or linear (the paper's
  // piecewise-linear surface).
  Render render = Render::cubic;
  SlopeLimiter slopes = SlopeLimiter::mc4;  // slope limiter of the cubic render
  // How an input pixel was made (AcquisitionModel): box (default), the
  // output's footprint averages reproduce the input (the consistent
  // reconstruction); point: the surface interpolates the samples, no
  // correction.
  AcquisitionModel model;
  // Box model: a pixel whose 3x3 neighbourhood one straight edge between
  // two flat levels explains is drawn as that edge.
  bool step_edges = true;
  std::function<void(const std::string&)> log;  // verbose lines; may be empty
  // Speed and memory (docs/performance.md). Regions of the parallel
  // optimizer in rows of input pixels: 0 automatic, < 0
  // one region (the plain sequential order).
  int region_rows = 0;
  // Tiles: bands of tile_rows input rows, full width, with overlapping
  // margins, each triangulated, optimized and rendered on its own; the
  // output is the untiled one, bit for bit. 0: automatic (tiles only when
  // the whole image would need more than max_memory bytes), < 0: never.
  // Only under the region schedule (region_rows > 0, or automatic on
  // images of more than 2 * default_region_triangles triangles). Under a
  // consistent model the margins also cover the reconstruction's reach
  // (consistent_reconstruction.hpp).
  int tile_rows = 0;
  // The whole image's consistent reconstruction, streamed (box model at
  // integer scales, output_rows set), draws from meshes of bands of
  // mesh_band_rows input rows, each triangulated and optimized with
  // margins when its wavefront reaches them and freed once it has passed:
  // the same output bit for bit, with two bands' meshes held instead of
  // the image's. 0: automatic (images tall enough that two bands and their
  // margins are at most half the rows), < 0: one mesh. Only
  // under the region schedule, as tile_rows.
  int mesh_band_rows = 0;
  // A memory target for the job, in bytes (the process's resident pages
  // included): tiles, and for files the bands read and written
  // (upscale_file), are sized by a memory model to stay under it (not a
  // hard cap: docs/performance.md), and a job that cannot is refused with
  // the size to give. 0: automatic (tiles past half the
  // physical memory, bands past what is available).
  long long max_memory = 0;
  Progress* progress = nullptr;     // stages and work done, for a progress bar; may be null
  // Streaming (io/band_writer.hpp): when set, the output is handed to this
  // in bands of rows, top to bottom, each row once, and upscale() returns
  // an empty image. Under the point model each band is rendered on its
  // own (in tiles, each tile), so the whole output is never held; the
  // consistent reconstruction holds the whole output and hands out each band as soon
  // as its last, footprint-local steps are done (box model at integer
  // scales; other models and scales once the whole output is).
  // The rows are those of the returned image, bit for bit.
  std::function<void(Image rows, int first_row)> output_rows;
  int output_band_rows = 0;         // rows per band handed out; 0: about 8 MB of floats (in tiles, each
                                    // tile's rows at once)
};

}  // namespace ddt
