#pragma once
// The single-image super-resolution evaluation protocol, as a library.
//
// Protocol on a directory of ground-truth images (Set5, Set14, ...), for
// every image (sorted by file name), every scale s and every method:
//   1. HR = the image cropped (top-left kept) so both sides are multiples
//      of s; alpha dropped (colour: channels 0..2, grey: channel 0).
//   2. LR = matlab_imresize_bicubic(HR, 1/s), rounded to 8 bits.
//   3. SR = method(LR) at HR's size; only this call is timed (steady_clock).
//   4. SR rounded to 8 bits: the published tables score uint8 outputs
//      (MATLAB's imresize of a uint8 LR returns uint8), so every method is
//      scored the way the reference bicubic row was.
//   5. PSNR and SSIM on BT.601 Y with s pixels shaved (metrics.hpp).
// Synthetic protocol (synthetic_scenes.hpp), for every scene and scale s:
//   HR = render_scene(scene, W s, H s), LR = render_scene(scene, W, H) —
//   both box-filtered renderings of the same analytic scene, so no
//   resampler enters the reference — then steps 3 and 5 (no 8-bit rounding),
//   and the measures of edge_sharpness.hpp on SR (EvalRow): the truth-based
//   halo against HR (as a fraction of the scene's step, the range of HR per
//   channel; one input pixel shaved like the scores) on every scene, and the
//   edge sharpness on the straight step edges.
//
// Images are processed one after another: the methods are themselves
// multithreaded (OIIO, TBB), and running images side by side would make
// the measured seconds depend on what else happens to be running.
//
// Errors: ddt::Error with a one-line message (unreadable file, empty
// directory, unknown method, an image smaller than a scale, a method that
// fails or returns the wrong size — the message names the method).

#include "util/image.hpp"
#include "pipeline/upscale.hpp"

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace ddt {

// One score: a row of the CSV `image,scale,method,psnr,ssim,seconds` (in
// synthetic mode followed by `halo,rise_width,wobble,edge_offset,overshoot`).
struct EvalRow {
  std::string image;   // file name (set mode) or scene name (synthetic mode)
  int scale = 0;
  std::string method;
  double psnr = 0;     // dB on Y; +infinity for a perfect result
  double ssim = 0;
  double seconds = 0;  // wall time of the upscaling call alone
  // Synthetic mode only, NaN otherwise (edge_sharpness.hpp):
  // truth_halo (the scene's step), in percent, every scene;
  double halo = std::numeric_limits<double>::quiet_NaN();
  // measure_edge_sharpness on the straight step edges (Scene::step_edge):
  // rise width, wobble and offset of the mid-level contour in input pixels,
  // overshoot in percent of the step.
  double rise_width = std::numeric_limits<double>::quiet_NaN();
  double wobble = std::numeric_limits<double>::quiet_NaN();
  double edge_offset = std::numeric_limits<double>::quiet_NaN();
  double overshoot = std::numeric_limits<double>::quiet_NaN();
};

// The mean of the rows of one (method, scale).
struct EvalMean {
  std::string method;
  int scale = 0;
  int images = 0;
  double psnr = 0, ssim = 0, seconds = 0;  // arithmetic means over the images
};

// An upscaler under test: `run` enlarges lr to out_width x out_height.
struct EvalMethod {
  std::string name;
  std::function<Image(const Image& lr, int out_width, int out_height)> run;
};

// The method names make_eval_methods() accepts:
//   ddt           ddt::upscale with the given options; with a cost list, one
//                 method per cost, named "ddt-<cost>"
//   ddt-<cost>    ddt::upscale with that cost
//   delaunay      ddt::upscale without optimization (the initial Delaunay mesh)
//   bicubic       the protocol's reference, matlab_imresize_bicubic
//   bicubic-oiio  classic_resize "bicubic" (Catmull-Rom through OpenImageIO)
//   lanczos, bilinear, nearest   classic_resize
//   opencv-lanczos4, opencv-cubic, vips-nohalo   peer_resize (other libraries)
std::vector<std::string> eval_method_names();

// Builds the methods named in `names`, in that order.
// Inputs:
//   names        entries of eval_method_names() (ddt-<cost> for any cost)
//   ddt_costs    costs expanding "ddt"; empty: one "ddt" with ddt_options.cost
//   ddt_options  options of every DDT variant (its cost replaced per variant)
// Errors: throws ddt::Error for an unknown name or cost (listing the valid
// ones) or a name given twice.
std::vector<EvalMethod> make_eval_methods(const std::vector<std::string>& names,
                                          const std::vector<std::string>& ddt_costs,
                                          const UpscaleOptions& ddt_options);

// Runs every method once on a tiny image, so a bad option (an unknown cost,
// say) fails at once rather than after minutes of work; also warms caches.
// Errors: rethrows a method's failure as ddt::Error prefixed with its name.
void check_eval_methods(const std::vector<EvalMethod>& methods);

struct EvalOptions {
  std::vector<int> scales{2, 3, 4};  // each >= 2
  std::vector<EvalMethod> methods;   // from make_eval_methods()
  int synthetic_size = 64;           // W = H of the synthetic LR renderings
  // Called before an image (or scene) is processed; index is 0-based.
  std::function<void(const std::string& name, int index, int count)> progress;
  // Called with the rows of one image (or scene) once it is scored.
  std::function<void(const std::vector<EvalRow>& rows)> on_image;
};

// The image files of `dir` (extensions png, jpg, jpeg, bmp, tif, tiff in any
// case; no subdirectories), sorted by file name.
// Errors: throws if dir is not a readable directory.
std::vector<std::string> list_images(const std::string& dir);

// Steps 1-5 for one ground-truth image.
// Inputs:  name  the row's image column;  hr  values in 0..1;  scales, methods  as in EvalOptions
// Outputs: rows ordered by scale, then method
std::vector<EvalRow> evaluate_image(const std::string& name, const Image& hr,
                                    const std::vector<int>& scales,
                                    const std::vector<EvalMethod>& methods);

// The protocol over every image of `dir` (list_images).
// Errors: throws if the directory holds no image.
std::vector<EvalRow> evaluate_set(const std::string& dir, const EvalOptions& options);

// The synthetic protocol over standard_scenes().
std::vector<EvalRow> evaluate_synthetic(const EvalOptions& options);

// Means per (method, scale), ordered by scale, then by the methods' first
// appearance in `rows`.
std::vector<EvalMean> mean_by_method_and_scale(const std::vector<EvalRow>& rows);

// The edge measures of one (method, scale) over the rows that have them
// (the step-edge scenes): means and worst cases.
struct EvalEdgeSummary {
  std::string method;
  int scale = 0;
  int edges = 0;                                // rows with a rise width
  double rise_width = 0, rise_width_max = 0;    // input pixels
  double wobble = 0, wobble_max = 0;            // input pixels
  double overshoot_max = 0;                     // percent of the step
  double halo_max = 0;                          // percent of the step, over the same rows
};

// One summary per (method, scale) that has edge rows, in the order of
// mean_by_method_and_scale. Rows whose rise width is NaN are skipped.
std::vector<EvalEdgeSummary> edge_summary_by_method_and_scale(const std::vector<EvalRow>& rows);

// Writes rows as CSV with exactly the header `image,scale,method,psnr,ssim,seconds`,
// one row each, in order (PSNR of a perfect result is written "inf"). With
// synthetic_columns, five more: `halo,rise_width,wobble,edge_offset,overshoot`
// (EvalRow; a measure not taken, NaN, is an empty field). Written to a
// temporary file in the target's directory, then renamed over `path`.
// Errors: throws ddt::Error if the file cannot be written; `path` is then untouched.
void write_eval_csv(const std::string& path, const std::vector<EvalRow>& rows, bool synthetic_columns = false);

}  // namespace ddt
