// Volumes on the command line:
//   ddtscale in.nrrd out.nrrd --scale 4 [--cost variance] [--compare trilinear] [--picture views.png]
//   ddtscale volume-eval [--size 32 --scale 4 --pictures DIR --table FILE]
//   ddtscale volume-eval --series [--size 32 --steps 16 --scale 2 --time-scale 4]
//   ddtscale volume-field NAME out.nrrd [--size 32] [--steps 16]

#include "commands.hpp"
#include "whole_number.hpp"

#include "core/costs.hpp"
#include "util/error.hpp"
#include "io/image_io.hpp"
#include "util/size_limits.hpp"
#include "eval/volume_experiments.hpp"
#include "eval/volume_fields.hpp"
#include "io/safe_file.hpp"
#include "io/volume_io.hpp"
#include "eval/volume_pictures.hpp"
#include "eval/volume_series_experiments.hpp"
#include "volume/volume_tiles.hpp"
#include "volume/volume_upscale.hpp"
#include "util/thread_limit.hpp"
#include "util/timing.hpp"

#include <CLI/CLI.hpp>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>

namespace fs = std::filesystem;

namespace {

using ddt::seconds_since;

double peak_memory_mb() {
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;  // Linux reports kilobytes
}

// "N", "XxYxZ" or "XxYxZxT" -> sizes >= 1 (size[3] = 0 when no T is given);
// throws ddt::Error.
std::array<int, 4> parse_size(const std::string& text) {
  std::array<int, 4> size{0, 0, 0, 0};
  char extra = 0;
  const int n = std::sscanf(text.c_str(), "%dx%dx%dx%d%c", &size[0], &size[1], &size[2], &size[3], &extra);
  if (n == 1) size[1] = size[2] = size[0];
  bool good = n == 1 || n == 3 || n == 4;
  for (int a = 0; a < (n == 4 ? 4 : 3); ++a) good = good && size[a] >= 1 && size[a] <= 65536;
  if (!good) throw ddt::Error("--size wants N, XxYxZ or XxYxZxT between 1 and 65536, got '" + text + "'");
  return size;
}

// out.nrrd + "trilinear" -> out.trilinear.nrrd (same directory and extension).
std::string sibling_path(const std::string& output, const std::string& tag) {
  const fs::path p(output);
  return (p.parent_path() / (p.stem().string() + "." + tag + p.extension().string())).string();
}

std::string size_text(const std::array<int, 4>& n) {
  return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]) +
         (n[3] > 1 ? "x" + std::to_string(n[3]) : std::string());
}
std::string size_text(const ddt::Volume& v) { return size_text(v.size()); }

int fail(const char* who, const std::exception& e) {
  std::cerr << who << e.what() << "\n";
  return 1;
}

// The memory the job holds at least, per channel: the input and the output
// as floats (8 bytes an output voxel with the stored copy and the ownership
// count), one more output per --compare method, and for the mesh methods the
// triangulation (about 0.5 KB an input voxel in 3D, 6 tetrahedra; in 4D
// 24 simplices a sample, about 1.7 KB measured at 32^3 x 16, docs/volumes.md) and the cubic
// render's gradients (D floats an input voxel).
// mesh_voxels: the input voxels of the largest mesh held (a tile's, with
// its margins, under --tile-slices).
double volume_job_bytes(ddt::VolumeMethod method, std::size_t compares, double in_voxels, double mesh_voxels,
                        double out_voxels, int channels, bool series) {
  const bool mesh = ddt::is_mesh_method(method);
  const double mesh_bytes = series ? 1800.0 : 512.0;
  return channels * (4.0 * in_voxels + (mesh ? 16.0 : 0.0) * mesh_voxels + 8.0 * out_voxels * double(1 + compares)) +
         (mesh ? mesh_bytes * mesh_voxels : 0.0);
}


// The volume command's arguments, as given.
struct VolumeArguments {
  std::string input, output, size_spec, method = "ddt", cost = "variance", picture, type = "same",
                                        encoding = "same", render = "cubic", slopes = "mc4";
  double scale = 0, time_scale = 0, tolerance = 1e-9, iso = NAN, presmooth = -1;
  std::vector<std::string> compare;
  long long max_voxels = ddt::default_max_voxels;
  int threads = 0;
  bool verbose = false, quiet = false, loose_tiles = false;
  ddt::VolumeReadOptions read_options;
  ddt::VolumeTiling tiling;
  // Set after parsing: whether --scale and --time-scale were given, and --size read.
  bool scale_given = false, time_given = false;
  std::array<int, 4> size_given{};
  VolumeArguments() { tiling.margin_slices = -1; }  // unset
};

void add_volume_options(CLI::App& app, VolumeArguments& a) {
  app.add_option("input", a.input, "input volume (.nrrd or .nhdr; raw, gzip, ...; 8/16/32-bit integer or float; "
                 "3 axes, or 4 for a series x, y, z, t; channels on a leading non-spatial axis: kind vector, "
                 "RGB-color, 3-vector, ...)")
      ->required();
  app.add_option("output", a.output, "output volume (.nrrd or .nhdr); keeps the input's sample type and encoding")
      ->required();
  app.add_option("-s,--scale", a.scale,
                 "magnification, any real > 0 (e.g. 4 or 2.5), the same on every axis (a series' time too, "
                 "unless --time-scale)");
  app.add_option("--time-scale", a.time_scale,
                 "series: magnification of the time axis, any real > 0: n steps become floor((n - 1) * T) + 1, "
                 "output step g at the instant g / T (the steps are instants: at a whole T every input step is "
                 "kept); alone, space keeps its size");
  app.add_option("--size", a.size_spec,
                 "output size instead of --scale: N (a cube), XxYxZ voxels, or XxYxZxT for a series (with XxYxZ "
                 "a series keeps its steps unless --time-scale)");
  app.add_option("--method", a.method,
                 "ddt (default), delaunay (no flips), trilinear or tricubic; series: ddt, delaunay, quadrilinear "
                 "(linear in space and time) or tricubic-linear (Catmull-Rom in space, linear in time)")
      ->check(CLI::IsMember(ddt::volume_series_upscale_methods()))
      ->capture_default_str();
  app.add_option("--cost", a.cost, "flip cost: " + ddt::cost_names_joined())->capture_default_str();
  app.add_option("--render", a.render,
                 "field drawn on the tetrahedra (ddt, delaunay): cubic (a cubic Bézier tetrahedron from the values "
                 "and limited slopes at its vertices, default) or linear (the paper's)")
      ->check(CLI::IsMember(ddt::render_names()))
      ->capture_default_str();
  app.add_option("--slopes", a.slopes, "cubic render: slope limiter of the vertex gradients: mc4, mc, central, minmod")
      ->check(CLI::IsMember(ddt::slope_limiter_names()))
      ->capture_default_str();
  app.add_option("--compare", a.compare,
                 "also write the volume enlarged by this method beside the output (out.METHOD.nrrd): "
                 "trilinear, tricubic, delaunay; series: quadrilinear, tricubic-linear, delaunay (comma-separated "
                 "for several)")
      ->delimiter(',')
      ->check(CLI::IsMember({"trilinear", "tricubic", "delaunay", "quadrilinear", "tricubic-linear"}));
  app.add_option("--picture", a.picture,
                 "write a PNG of the middle slices and a maximum-intensity projection: one column per "
                 "--compare method, then DDT; series: the middle x-y and x-z slices of the middle output step "
                 "and the x-t plane at the middle y and z");
  app.add_option("--iso", a.iso, "with --picture: add a row of shaded isosurfaces at this value");
  app.add_option("--type", a.type, "output sample type: same, uint8, int8, uint16, int16, uint32, int32, float32, float64")
      ->capture_default_str();
  app.add_option("--encoding", a.encoding, "output encoding: same, raw, gzip, bzip2, ascii, hex")->capture_default_str();
  app.add_option("--tolerance", a.tolerance, "a flip must lower the local cost by more than this fraction")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--tile-slices,--time-tile", a.tiling.tile_slices,
                 "reconstruct N input slices of the last axis at a time (z of a 3D volume, time steps of a series), "
                 "plus margins on either side, which bounds the mesh's memory; the result is the untiled one bit for "
                 "bit (the margins are widened as the optimizer needs) unless --loose-tiles; needs a whole scale "
                 "along that axis (default: the whole volume)")
      ->check(whole_number(1));
  app.add_option("--tile-margin,--time-margin", a.tiling.margin_slices,
                 "with --tile-slices: slices reconstructed on either side of a tile: with --loose-tiles exactly this "
                 "(default 4); else the least, whole slabs of the optimizer's schedule (from what 3 of its phases "
                 "need, widened as it needs more)")
      ->check(whole_number(0, 100000));
  app.add_flag("--loose-tiles", a.loose_tiles,
               "with --tile-slices: keep the margin as given (cheaper; the result then differs near the joins)");
  app.add_option("--presmooth", a.presmooth,
                 "graduated optimization (ddt): flip first on the samples smoothed in space by a Gaussian of this "
                 "sigma (voxels), then on the samples; default 1 for series, 0 (off) for 3D volumes")
      ->check(CLI::Range(0.0, 16.0));
  app.add_option("--max-voxels", a.max_voxels, "refuse outputs with more voxels than this")
      ->check(whole_number(1))
      ->capture_default_str();
  app.add_option("--max-input-voxels", a.read_options.max_voxels,
                 "refuse inputs with more voxels than this, from the header before reading the data (default: "
                 "the physical memory / 1024)")
      ->check(whole_number(1))
      ->capture_default_str();
  app.add_option("--threads", a.threads,
                 "threads to use (default: all cores; more than the cores are not used); the output is the same "
                 "for any number")
      ->check(whole_number(1));
  app.add_flag("-v,--verbose", a.verbose,
               "report stages, flips of each kind per iteration, cost, times and peak memory");
  app.add_flag("-q,--quiet", a.quiet, "print nothing but errors");
  app.add_flag("--any-data-file", a.read_options.any_data_path,
               "let a detached header name a data file outside its directory (absolute or '..' paths)");
  app.footer(
      "\nCosts (the paper's weighted content, sum over tetrahedra of volume * weight):\n"
      "  variance   weight = variance of the four vertex values (default; the paper's 3D experiments)\n"
      "  sederberg  weight = mean over the four faces of |g1||g2| - g1.g2 (gradients on the two\n"
      "             tetrahedra sharing the face)\n"
      "Channels (RGB, vectors): one tetrahedrization for all of them, the cost summed over channels\n"
      "(up to 8); the output keeps the channel axis and its kind; --picture shows the first channel.\n"
      "Output voxel (X, Y, Z) samples the input at ((X + 0.5) / sx, ...); outside the voxel centres'\n"
      "box it takes the value of the nearest point of the box. Spacing, space directions and origin\n"
      "are scaled so every output sample keeps its world position.\n"
      "Series (4 axes x, y, z, t): time steps are instants (node-centred) unless the header's time axis\n"
      "says \"centers: cell\": n steps enlarged by T become (n - 1) * T + 1, output step T * k is input\n"
      "step k, and the output's time axis is written node-centred with spacing / T, same min and max.\n"
      "Memory: about 24 4-simplices per input sample (some 1.7 KB); --max-voxels and the physical memory\n"
      "bound the job before any work.\n"
      "Other volume commands: ddtscale volume-eval --help, ddtscale volume-field --help.\n"
      "Example: ddtscale head.nrrd head_x4.nrrd --scale 4 --compare trilinear --picture head.png -v\n"
      "Series: ddtscale beat.nrrd beat_x2.nrrd --scale 2 --time-scale 4 --compare quadrilinear --picture beat.png");
}

// The checks that need no file, after parsing; sets the given-flags and
// the size read from --size. Throws ddt::Error.
void check_volume_arguments(VolumeArguments& a, const CLI::App& app) {
  if (!ddt::is_volume_path(a.input))
    throw ddt::Error("the input '" + a.input + "' is not a volume: give a .nrrd or .nhdr file");
  if (!ddt::is_volume_path(a.output))
    throw ddt::Error("cannot write '" + a.output + "': a volume is written as .nrrd or .nhdr (pictures: --picture)");
  if (!(a.tolerance >= 0.0 && a.tolerance <= 1.0)) throw ddt::Error("--tolerance must be a number in [0, 1]");
  ddt::check_volume_output_path(a.output, a.input, a.read_options);
  for (const auto& m : a.compare) ddt::check_volume_output_path(sibling_path(a.output, m), a.input, a.read_options);
  if (!a.picture.empty()) ddt::check_output_path(a.picture, a.input);
  a.time_given = app.count("--time-scale") > 0;
  a.scale_given = app.count("--scale") > 0;
  if (a.scale_given && !a.size_spec.empty()) throw ddt::Error("give either --scale or --size, not both");
  if (!a.scale_given && a.size_spec.empty() && !a.time_given)
    throw ddt::Error("give the magnification: --scale S (and --time-scale T), or --size N, XxYxZ or XxYxZxT");
  // As images say it (--scale 0 included); from here on, 0 means not given.
  if (a.scale_given && (!(a.scale > 0) || !std::isfinite(a.scale))) throw ddt::Error("--scale must be a positive number");
  if (a.time_given && (!(a.time_scale > 0) || !std::isfinite(a.time_scale)))
    throw ddt::Error("--time-scale must be a positive number");
  a.size_given = a.size_spec.empty() ? std::array<int, 4>{} : parse_size(a.size_spec);
  if (a.size_given[3] != 0 && a.time_given) throw ddt::Error("give the steps either in --size or by --time-scale");
}

// The whole job sized from the input's header (size `in`, `channels`),
// before its data is read: the output size into `out`, then the limits and
// the memory. Throws ddt::Error with what to give where it does not fit.
void size_volume_job(const VolumeArguments& a, ddt::VolumeMethod method, const std::array<int, 4>& in, int channels,
                     std::array<int, 4>& out) {
  // Is the input a series? Its header says so; time steps are instants
  // (the header's centring is honoured after the read: this only sizes the job).
  const bool series = in[3] > 1;
  if (!series && (a.time_given || a.size_given[3] > 1))
    throw ddt::Error("--time-scale and a time size apply to volume series (4 axes); '" + a.input +
                     "' is a 3D volume");
  const double space = a.scale != 0 ? a.scale : 1.0, time = a.time_given ? a.time_scale : space;
  for (int k = 0; k < 4; ++k) {
    const double n = k < 3 ? std::round(in[k] * space) : ddt::tiled_output_slices(in[3], time, true);
    if (n > 65536) throw ddt::Error("--scale gives an output larger than --max-voxels");
    out[k] = static_cast<int>(std::max(1.0, n));
  }
  if (!a.size_spec.empty())
    for (int k = 0; k < 4; ++k)
      if (k < 3 || a.size_given[3] != 0) out[k] = a.size_given[k];
  ddt::check_size_limit("output", size_text(out), ddt::checked_product({out[0], out[1], out[2], out[3]}),
                        a.max_voxels, "--max-voxels");
  const double in_voxels = double(in[0]) * in[1] * in[2] * in[3];
  const double out_voxels = double(out[0]) * out[1] * out[2] * out[3];
  const int axis = series ? 3 : 2;
  const double slice_voxels = in_voxels / in[axis];
  // A tile's mesh: its slices and its margins (loose, or the first guess of exact ones).
  auto tile_voxels = [&](int slices) {
    const int margin = a.tiling.margin_slices >= 0 ? a.tiling.margin_slices : 4;
    return std::min(in_voxels, slice_voxels * (slices + 2.0 * (a.loose_tiles ? margin : std::max(margin, 48))));
  };
  const double mesh_voxels = a.tiling.tile_slices > 0 ? tile_voxels(a.tiling.tile_slices) : in_voxels;
  const double bytes = volume_job_bytes(method, a.compare.size(), in_voxels, mesh_voxels, out_voxels, channels, series);
  if (a.tiling.tile_slices == 0 && ddt::is_mesh_method(method) && bytes > static_cast<double>(ddt::available_memory())) {
    // Would tiles fit? The output is still held whole.
    int fits = 0;
    for (int n = in[axis] / 2; n >= 1 && fits == 0; n /= 2)
      if (volume_job_bytes(method, a.compare.size(), in_voxels, slice_voxels * (n + 8), out_voxels, channels,
                           series) <= static_cast<double>(ddt::available_memory()))
        fits = n;
    if (fits > 0)
      throw ddt::Error("this job needs at least " + std::to_string(static_cast<long long>(bytes / 1048576)) +
                       " MB of memory, " + std::to_string(ddt::available_memory() / 1048576) +
                       " MB are available; in tiles it fits: give --tile-slices " + std::to_string(fits) +
                       " --loose-tiles (or --tile-slices alone for the untiled result, with wider margins)");
  }
  ddt::check_memory_fits("this job", bytes);
}

// Tiles along the last axis (--tile-slices): the output is held whole (the
// NRRD is written at once), the mesh a tile at a time.
ddt::Volume upscale_volume_in_tiles(const ddt::Volume& src, const std::array<int, 4>& out,
                                    const ddt::VolumeUpscaleOptions& options, VolumeArguments& a,
                                    const std::function<void(const std::string&)>& log) {
  if (!ddt::is_mesh_method(options.method)) throw ddt::Error("--tile-slices applies to the ddt and delaunay methods");
  ddt::VolumeTiling& tiling = a.tiling;
  tiling.axis_scale = options.last_axis.scale;
  tiling.exact = !a.loose_tiles;
  if (tiling.margin_slices < 0) tiling.margin_slices = a.loose_tiles ? 4 : 0;
  ddt::Volume result(out, src.channels, 0.0f);
  const bool series = src.nt > 1;
  const int axis = series ? 3 : 2;
  const std::size_t in_slice = src.voxels.size() / src.size()[axis];
  const std::size_t out_slice = result.voxels.size() / out[axis];
  ddt::VolumeTilingStats ts;
  ddt::upscale_in_tiles(
      src.size(), out, src.channels, options, tiling,
      [&](int k, float* samples) {
        std::copy_n(src.voxels.begin() + static_cast<std::ptrdiff_t>(k * in_slice), in_slice, samples);
      },
      [&](const float* samples, int k) {
        std::copy_n(samples, out_slice, result.voxels.begin() + static_cast<std::ptrdiff_t>(k * out_slice));
      },
      &ts);
  log(std::string("tiles: ") + std::to_string(ts.tiles) + " of " + std::to_string(tiling.tile_slices) +
      (series ? " steps" : " slices") + ", margin " + std::to_string(ts.margin_slices) +
      (tiling.exact ? " (exact; slabs of " + std::to_string(ts.region_slices) + ", " + std::to_string(ts.reruns) +
                          " tiles run again with a wider margin)"
                    : " (loose)") +
      ", " + std::to_string(ts.flips) + " flips");
  return result;
}

// --picture: a column per --compare method, then the result; several
// channels show the first.
void write_volume_picture(const VolumeArguments& a, const ddt::Volume& src, const ddt::Volume& result,
                          const std::vector<ddt::Volume>& baselines, const std::array<int, 4>& out,
                          const std::function<void(const std::string&)>& log) {
  const bool series = src.nt > 1, iso = std::isfinite(a.iso);
  std::vector<ddt::Volume> firsts;
  if (src.channels > 1) {
    for (const auto& b : baselines) firsts.push_back(ddt::volume_channel(b, 0));
    firsts.push_back(ddt::volume_channel(result, 0));
  }
  std::vector<const ddt::Volume*> columns;
  for (const auto& b : src.channels > 1 ? firsts : baselines) columns.push_back(&b);
  if (src.channels == 1) columns.push_back(&result);
  double lo = 0, hi = 1;
  ddt::value_range(src.channels > 1 ? ddt::volume_channel(src, 0) : src, lo, hi);
  std::vector<ddt::VolumeView> rows = {ddt::VolumeView::slice_xy, ddt::VolumeView::slice_xz,
                                       ddt::VolumeView::slice_yz, ddt::VolumeView::mip_z};
  ddt::IsoView iso_view;
  if (iso) {
    rows.push_back(ddt::VolumeView::isosurface);
    iso_view.level = a.iso;
  }
  if (series) {
    // The middle output step (between two input steps at even time scales) and the x-t plane.
    rows = {ddt::VolumeView::slice_xy, ddt::VolumeView::slice_xz};
    if (iso) rows.push_back(ddt::VolumeView::isosurface);
  }
  const ddt::Image views = series ? ddt::compare_series_views(columns, out[3] / 2, rows, lo, hi, iso_view)
                                  : ddt::compare_views(columns, rows, lo, hi, iso_view);
  ddt::write_image(a.picture, views, ddt::SampleFormat::uint8);
  log("picture: " + a.picture + " (columns: " + (a.compare.empty() ? "" : "compare methods, then ") + a.method +
      (series ? "; rows: x-y, x-z middle slices of step " + std::to_string(out[3] / 2) +
                    (iso ? ", isosurface" : "") + ", the x-t plane"
              : "; rows: x-y, x-z, y-z middle slices, MIP along z" + std::string(iso ? ", isosurface" : "")) +
      ")");
}

int run_volume_upscale(int argc, char** argv) {
  VolumeArguments a;
  CLI::App app{"ddtscale (volumes): enlarge a NRRD volume (scalar, RGB or vector) by data-dependent tetrahedrization.\n"
               "The voxels become a 3D scalar field, tetrahedrized (Delaunay, then bistellar 2-3, 3-2, 4-4 and\n"
               "hull 2-2 flips that lower the weighted content of the paper's cost) so that long thin\n"
               "tetrahedra follow surfaces; the field on them (cubic, or the paper's linear) is scan-converted at the\n"
               "new size. A volume series (4 axes: x, y, z, t) is done the same way in 4D: the Delaunay mesh of\n"
               "the 4D grid, the generic flips, the cubic or linear field on its 4-simplices.",
               "ddtscale"};
  add_volume_options(app, a);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    std::cerr << "ddtscale: " << e.what() << " (see ddtscale in.nrrd out.nrrd --help)\n";
    return 2;
  }

  try {
    ddt::find_cost(a.cost);
    const bool same_type = a.type == "same", same_encoding = a.encoding == "same";
    const ddt::VolumeSampleType forced_type =
        same_type ? ddt::VolumeSampleType::float32 : ddt::parse_sample_type(a.type);
    const ddt::VolumeEncoding forced_encoding =
        same_encoding ? ddt::VolumeEncoding::raw : ddt::parse_encoding(a.encoding);
    check_volume_arguments(a, app);
    const ddt::VolumeMethod volume_method = ddt::volume_method_by_name(a.method);

    const bool verbose = a.verbose;
    const std::function<void(const std::string&)> log = [verbose](const std::string& line) {
      if (verbose) std::cerr << line << "\n";
    };
    const auto thread_limit = ddt::limit_threads(a.threads);
    std::array<int, 4> out{0, 0, 0, 0};
    a.read_options.check = [&](const std::array<int, 4>& in, int channels) {
      size_volume_job(a, volume_method, in, channels, out);
    };
    auto t0 = std::chrono::steady_clock::now();
    const ddt::VolumeFile file = ddt::read_volume(a.input, a.read_options);
    const ddt::Volume& src = file.volume;
    log("read: " + a.input + ", " + size_text(src) +
        (src.channels > 1 ? ", " + std::to_string(src.channels) + " channels" : std::string()) + ", " +
        ddt::sample_type_name(file.type) + ", " + ddt::encoding_name(file.encoding) + ", " +
        std::to_string(seconds_since(t0)) + " s");

    const bool series = src.nt > 1;
    if (!series && (volume_method == ddt::VolumeMethod::quadrilinear ||
                    volume_method == ddt::VolumeMethod::tricubic_linear))
      throw ddt::Error("--method " + a.method + " is for volume series (4 axes); '" + a.input + "' is a 3D volume");
    for (const auto& m : a.compare) {
      if (series && (m == "trilinear" || m == "tricubic"))
        throw ddt::Error("--compare " + m + " is for 3D volumes; a series compares with quadrilinear or "
                         "tricubic-linear");
      if (!series && (m == "quadrilinear" || m == "tricubic-linear"))
        throw ddt::Error("--compare " + m + " is for volume series; a 3D volume compares with trilinear or tricubic");
    }
    const ddt::VolumeSampleType out_type = same_type ? file.type : forced_type;
    const ddt::VolumeEncoding out_encoding = same_encoding ? file.encoding : forced_encoding;
    ddt::VolumeUpscaleOptions options;
    options.method = volume_method;
    options.cost = a.cost;
    options.relative_tolerance = a.tolerance;
    options.render = ddt::render_by_name(a.render);
    options.slopes = ddt::slope_limiter_by_name(a.slopes);
    options.node_centred = file.node_centred;
    options.presmooth = ddt::presmooth_in_space(series, a.presmooth);
    if (verbose) options.log = log;
    // The time axis counted and sampled as image sequences are (a fractional
    // --time-scale samples the instants g / T); a header that says its steps
    // are cells: n steps become n * T.
    if (series && a.size_given[3] == 0)
      out[3] = ddt::scale_time_axis(src.nt, a.time_given ? a.time_scale : a.scale != 0 ? a.scale : 1.0, options);
    const ddt::Volume result = a.tiling.tile_slices > 0 ? upscale_volume_in_tiles(src, out, options, a, log)
                                                        : ddt::upscale_volume(src, out, options);
    char comment[240];
    const bool mesh_method = ddt::is_mesh_method(volume_method);
    std::snprintf(comment, sizeof comment, "ddtscale: %s enlarged to %s by %s%s%s%s%s%s", size_text(src).c_str(),
                  size_text(out).c_str(), a.method.c_str(), a.method == "ddt" ? ", cost " : "",
                  a.method == "ddt" ? a.cost.c_str() : "", mesh_method ? ", render " : "",
                  mesh_method ? a.render.c_str() : "",
                  series ? (file.node_centred[3] ? ", time node-centred" : ", time cell-centred") : "");
    t0 = std::chrono::steady_clock::now();
    ddt::write_volume(a.output, result, out_type, out_encoding, file.header.get(), comment, file.node_centred);
    log("write: " + a.output + ", " + ddt::sample_type_name(out_type) + ", " + ddt::encoding_name(out_encoding) +
        ", " + std::to_string(seconds_since(t0)) + " s");

    std::vector<ddt::Volume> baselines;
    for (const auto& m : a.compare) {
      ddt::VolumeUpscaleOptions o = options;
      o.method = ddt::volume_method_by_name(m);
      baselines.push_back(ddt::upscale_volume(src, out, o));
      const std::string path = sibling_path(a.output, m);
      ddt::write_volume(path, baselines.back(), out_type, out_encoding, file.header.get(),
                        "ddtscale: " + size_text(src) + " enlarged by " + m, file.node_centred);
      log("compare: " + path);
    }
    if (!a.picture.empty()) write_volume_picture(a, src, result, baselines, out, log);
    char line[120];
    std::snprintf(line, sizeof line, "peak memory: %.0f MB", peak_memory_mb());
    log(line);
    if (!a.quiet && !verbose)
      std::cerr << a.output << ": " << size_text(out) << " " << ddt::sample_type_name(out_type) << "\n";
    return 0;
  } catch (const std::bad_alloc&) {
    std::cerr << "ddtscale: out of memory (try a smaller output or --max-voxels)\n";
    return 1;
  } catch (const std::exception& e) {
    return fail("ddtscale: ", e);
  }
}

// volume-eval --series: the volume-series experiment (volume_series_experiments.hpp).
int run_volume_series_eval(const ddt::VolumeSeriesExperimentOptions& options,
                           const std::string& table, bool quiet) {
  ddt::VolumeSeriesExperimentOptions o = options;
  if (!quiet) o.log = [](const std::string& line) { std::cerr << line << "\n"; };
  const auto rows = ddt::run_volume_series_experiment(o);
  const std::string text = ddt::volume_series_experiment_table(rows);
  std::cout << text;
  if (!table.empty()) ddt::write_file_atomically(table, text);
  return 0;
}

int run_volume_eval(int argc, char** argv) {
  ddt::VolumeExperimentOptions options;
  ddt::VolumeSeriesExperimentOptions series_options;
  std::string pictures, table;
  std::vector<std::string> fields = options.fields, methods = options.methods,
                           picture_methods = options.picture_methods;
  bool quiet = false, series = false;
  CLI::App app{"The paper's 3D experiments: analytic volumes (sphere, hydrogen orbital) sampled at SIZE^3,\n"
               "enlarged by SCALE with each method and scored against the field sampled at the high\n"
               "resolution (RMSE, PSNR with peak 1). Prints a Markdown table.\n"
               "With --series, the volume-series experiment (4D): the moving, growing sphere sampled at\n"
               "SIZE^3 x STEPS, enlarged by SCALE in space and TIME-SCALE in time (node-centred: (STEPS - 1) *\n"
               "TIME-SCALE + 1 steps), scored against the field at the output's voxels and instants; methods\n"
               "quadrilinear, tricubic-linear, delaunay, ddt (the defaults change: --scale 2, --input-ss 4,\n"
               "--reference-ss 2).",
               "ddtscale volume-eval"};
  app.add_option("--size", options.size, "input size (a cube)")->capture_default_str()->check(whole_number(2, 512));
  app.add_option("--scale", options.scale, "integer magnification (with --series: in space, default 2)")
      ->capture_default_str()
      ->check(whole_number(1, 16));
  app.add_flag("--series", series, "run the volume-series experiment (4D; moving-sphere unless --fields names another) instead");
  app.add_option("--steps", series_options.steps, "--series: input time steps")
      ->capture_default_str()
      ->check(whole_number(2, 512));
  app.add_option("--time-scale", series_options.time_scale, "--series: integer magnification in time")
      ->capture_default_str()
      ->check(whole_number(1, 16));
  app.add_option("--fields", fields,
                 "fields (comma-separated): " + ddt::volume_field_names() + " (--series: one of " +
                     ddt::volume_series_field_names() + ")")
      ->delimiter(',');
  app.add_option("--methods", methods,
                 "methods (comma-separated): trilinear, tricubic, delaunay, ddt:COST (ddt = ddt:variance); "
                 "ddt and delaunay with -linear (the paper's render) or -cubic (the default), e.g. ddt-linear:variance; "
                 "--series: quadrilinear, tricubic-linear, delaunay, ddt (default: quadrilinear, tricubic-linear, "
                 "delaunay, ddt-linear, ddt)")
      ->delimiter(',');
  app.add_option("--pictures", pictures,
                 "write <field>-x<scale>.png views into this directory (--series: "
                 "<field>-x<scale>-t<time-scale>.png and -iso.png)");
  app.add_option("--picture-methods", picture_methods, "the columns after the reference in the pictures")
      ->delimiter(',');
  app.add_option("--table", table, "also write the Markdown table to this file");
  app.add_option("--input-ss", options.input_ss, "point samples per axis per input voxel (--series: default 4)")
      ->check(whole_number(1, 64))
      ->capture_default_str();
  app.add_option("--reference-ss", options.reference_ss,
                 "point samples per axis per reference voxel (--series: default 2)")
      ->check(whole_number(1, 64))
      ->capture_default_str();
  app.add_option("--iso", options.iso_level,
                 "the level of the isosurface pictures (default: the field's, sphere 0.5, hydrogen 0.1)")
      ->check(CLI::PositiveNumber);
  app.add_option("--quantize", options.quantize_bits,
                 "round the input samples to this many bits (8: an 8-bit data set, as the paper's hydrogen "
                 "volume); 0: keep floats")
      ->check(whole_number(0, 24))
      ->capture_default_str();
  app.add_flag("-q,--quiet", quiet, "print only the table");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    std::cerr << "ddtscale volume-eval: " << e.what() << " (see ddtscale volume-eval --help)\n";
    return 2;
  }
  try {
    if (series) {
      for (const char* only3d : {"--quantize", "--iso"})
        if (app.count(only3d)) throw ddt::Error(std::string(only3d) + " is for the 3D experiments, not --series");
      series_options.size = options.size;
      if (app.count("--scale")) series_options.scale = options.scale;
      if (app.count("--input-ss")) series_options.input_ss = options.input_ss;
      if (app.count("--reference-ss")) series_options.reference_ss = options.reference_ss;
      if (app.count("--fields")) {
        if (fields.size() != 1) throw ddt::Error("--series runs one field at a time, e.g. --fields moving-box");
        series_options.field = fields[0];
      }
      if (app.count("--methods")) series_options.methods = methods;
      if (app.count("--picture-methods")) series_options.picture_methods = picture_methods;
      series_options.picture_dir = pictures;
      return run_volume_series_eval(series_options, table, quiet);
    }
    for (const char* only4d : {"--steps", "--time-scale"})
      if (app.count(only4d)) throw ddt::Error(std::string(only4d) + " is for --series");
    options.fields = fields;
    options.methods = methods;
    options.picture_methods = picture_methods;
    options.picture_dir = pictures;
    if (!quiet) options.log = [](const std::string& line) { std::cerr << line << "\n"; };
    const auto rows = ddt::run_volume_experiments(options);
    const std::string text = ddt::volume_experiment_table(rows);
    std::cout << text;
    if (!table.empty()) ddt::write_file_atomically(table, text);
    return 0;
  } catch (const std::exception& e) {
    return fail("ddtscale volume-eval: ", e);
  }
}

int run_volume_field(int argc, char** argv) {
  std::string name, output, size_spec = "32", type = "float32", encoding = "raw";
  int ss = 8, steps = 16;
  bool list = false;
  CLI::App app{"Write an analytic test volume (box-filtered over each voxel) as NRRD. Values 0..1;\n"
               "integer types scale them to the type's maximum (uint8: 0..255).\nSeries fields (" +
                   ddt::volume_series_field_names() +
                   ") are written as 4-axis NRRDs\n(x, y, z, t; the time axis of kind time, node-centred: "
                   "step l is the instant t = l / (steps - 1)).",
               "ddtscale volume-field"};
  app.add_option("name", name, "field name (see --list)");
  app.add_option("output", output, "output volume (.nrrd or .nhdr)");
  app.add_option("--size", size_spec, "N (a cube) or XxYxZ voxels, or XxYxZxT for a series")->capture_default_str();
  app.add_option("--steps", steps, "series fields: time steps (unless --size gives them)")
      ->capture_default_str()
      ->check(whole_number(1, 65536));
  app.add_option("--supersample", ss, "point samples per axis per voxel")->capture_default_str()->check(whole_number(1, 64));
  app.add_option("--type", type, "sample type: uint8, uint16, float32, ...")->capture_default_str();
  app.add_option("--encoding", encoding, "raw, gzip, ...")->capture_default_str();
  app.add_flag("--list", list, "list the fields and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    std::cerr << "ddtscale volume-field: " << e.what() << " (see ddtscale volume-field --help)\n";
    return 2;
  }
  try {
    if (list) {
      for (const auto& f : ddt::volume_fields()) std::cout << f.name << "\t" << f.description << "\n";
      for (const auto& f : ddt::volume_series_fields())
        std::cout << f.name << "\t(series) " << f.description << "\n";
      return 0;
    }
    if (name.empty() || output.empty()) throw ddt::Error("give a field name and an output file (see --list)");
    std::array<int, 4> size = parse_size(size_spec);
    bool series = false;
    for (const auto& f : ddt::volume_series_fields()) series = series || f.name == name;
    if (!series && size[3] != 0) throw ddt::Error("'" + name + "' is a 3D field: --size N or XxYxZ");
    if (series && size[3] == 0) size[3] = steps;
    const ddt::VolumeSampleType t = ddt::parse_sample_type(type);
    const ddt::VolumeEncoding e = ddt::parse_encoding(encoding);
    std::string description;
    if (!series) description = ddt::find_volume_field(name).description;  // throws for unknown names
    else description = ddt::find_volume_series_field(name).description;
    ddt::check_size_limit("output", size_text(size), ddt::checked_product({size[0], size[1], size[2], size[3]}),
                          ddt::default_max_voxels, "--size");
    ddt::check_volume_output_path(output, "");
    ddt::Volume v = series ? ddt::sample_series_field(ddt::find_volume_series_field(name), size, ss)
                           : ddt::sample_field(ddt::find_volume_field(name), size[0], size[1], size[2], ss);
    const double peak = t == ddt::VolumeSampleType::uint8    ? 255.0
                        : t == ddt::VolumeSampleType::int8   ? 127.0
                        : t == ddt::VolumeSampleType::uint16 ? 65535.0
                        : t == ddt::VolumeSampleType::int16  ? 32767.0
                                                             : 1.0;
    for (float& x : v.voxels) x = static_cast<float>(x * peak);
    ddt::write_volume(output, v, t, e, nullptr, "ddtscale volume-field " + name + ": " + description);
    return 0;
  } catch (const std::exception& e) {
    return fail("ddtscale volume-field: ", e);
  }
}

}  // namespace

bool is_volume_command(int argc, char** argv) {
  if (argc >= 2 && (std::strcmp(argv[1], "volume-eval") == 0 || std::strcmp(argv[1], "volume-field") == 0))
    return true;
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] != '-' && ddt::is_volume_path(argv[i])) return true;
  return false;
}

int run_volume_command(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "volume-eval") == 0) return run_volume_eval(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "volume-field") == 0) return run_volume_field(argc - 1, argv + 1);
  return run_volume_upscale(argc, argv);
}
