#include "eval/volume_series_experiments.hpp"

#include "util/error.hpp"
#include "io/image_io.hpp"
#include "eval/isosurface_error.hpp"
#include "eval/volume_experiments.hpp"
#include "eval/volume_fields.hpp"
#include "eval/volume_pictures.hpp"
#include "volume/volume_upscale.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

namespace ddt {
namespace {

constexpr const char* reference_method = "reference (the field at the output's voxels)";

// volume_options_for's specs, and "ddt-unsmoothed": without the graduated
// optimization the command line runs on series.
VolumeUpscaleOptions series_options_for(const std::string& spec) {
  const bool unsmoothed = spec.rfind("ddt-unsmoothed", 0) == 0;
  VolumeUpscaleOptions o = volume_options_for(unsmoothed ? "ddt" + spec.substr(14) : spec);
  o.presmooth = unsmoothed ? std::array<double, 4>{} : presmooth_in_space(true);
  o.node_centred = {false, false, false, true};
  return o;
}

// RMSE over the output steps that fall between input steps (step % time_scale != 0).
double made_steps_rmse(const Volume& a, const Volume& b, int time_scale) {
  const std::size_t per_step = static_cast<std::size_t>(a.nx) * a.ny * a.nz * a.channels;
  double sum = 0;
  std::size_t count = 0;
  for (int t = 0; t < a.nt; ++t) {
    if (t % time_scale == 0) continue;
    for (std::size_t i = t * per_step; i < (t + 1) * per_step; ++i) {
      const double d = double(a.voxels[i]) - b.voxels[i];
      sum += d * d;
    }
    count += per_step;
  }
  return count ? std::sqrt(sum / count) : 0.0;
}

}  // namespace

std::vector<VolumeSeriesExperimentRow> run_volume_series_experiment(const VolumeSeriesExperimentOptions& options) {
  if (options.size < 2 || options.steps < 2 || options.scale < 1 || options.time_scale < 1)
    throw Error("series experiment: size and steps must be >= 2, scales >= 1");
  for (const auto& spec : options.methods) {
    VolumeUpscaleOptions o;
    try {
      o = series_options_for(spec);
    } catch (const Error&) {
      throw Error("unknown series method '" + spec +
                  "' (valid: quadrilinear, tricubic-linear, delaunay, ddt, ddt-unsmoothed)");
    }
    find_cost(o.cost);  // fail fast
  }
  if (!options.picture_dir.empty() && !std::filesystem::is_directory(options.picture_dir))
    throw Error("picture directory '" + options.picture_dir + "' does not exist");
  auto log = [&](const std::string& line) {
    if (options.log) options.log(line);
  };
  const VolumeSeriesField& field = find_volume_series_field(options.field);
  const int n = options.size, N = n * options.scale;
  const int steps_out = (options.steps - 1) * options.time_scale + 1;
  const Volume input = sample_series_field(field, {n, n, n, options.steps}, options.input_ss);
  const Volume reference = sample_series_field(field, {N, N, N, steps_out}, options.reference_ss);
  std::vector<VolumeSeriesExperimentRow> rows;
  std::map<std::string, Volume> results;
  auto score_isosurface = [&](const Volume& v, VolumeSeriesExperimentRow& row) {
    if (!field.surface_distance) return;
    const IsosurfaceError iso = isosurface_error(v, field.iso_level, field.surface_distance,
                                                 [&](int l) { return l % options.time_scale != 0; });
    row.iso_rms = iso.rms, row.iso_p99 = iso.p99;
    row.iso_normal_rms = iso.normal_rms, row.iso_normal_p99 = iso.normal_p99;
    row.iso_crossings = iso.crossings, row.iso_true_crossings = iso.true_crossings;
    // The kept steps alone (space only) tell the temporal share apart.
    row.iso_rms_kept = isosurface_error(v, field.iso_level, field.surface_distance,
                                        [&](int l) { return l % options.time_scale == 0; }).rms;
  };
  if (field.surface_distance) {
    // The metric's floor: the field itself, sampled as the output is.
    VolumeSeriesExperimentRow row;
    row.field = options.field;
    row.method = reference_method;
    score_isosurface(reference, row);
    char line[300];
    std::snprintf(line, sizeof line,
                  "%s, the field at the output's voxels: isosurface RMS %.3f voxel (p99 %.3f, %lld of %lld "
                  "crossings; kept steps %.3f), normal RMS %.2f degrees (p99 %.2f)",
                  options.field.c_str(), row.iso_rms, row.iso_p99, row.iso_crossings, row.iso_true_crossings,
                  row.iso_rms_kept, row.iso_normal_rms, row.iso_normal_p99);
    log(line);
    rows.push_back(row);
  }
  for (const std::string& spec : options.methods) {
    VolumeUpscaleStats st;
    const auto t0 = std::chrono::steady_clock::now();
    Volume out = upscale_volume(input, {N, N, N, steps_out}, series_options_for(spec), &st);
    VolumeSeriesExperimentRow row;
    row.field = options.field;
    row.method = spec;
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    row.rmse = volume_rmse(out, reference);
    row.psnr = 20 * std::log10(1.0 / row.rmse);
    row.psnr_made = 20 * std::log10(1.0 / made_steps_rmse(out, reference, options.time_scale));
    row.flips = st.flips.total() + st.presmooth_flips;  // the graduated optimization's first pass too
    row.simplices = st.tetrahedra;
    score_isosurface(out, row);
    char line[500];
    std::snprintf(line, sizeof line,
                  "%s %d^3 x %d steps, x%d space, x%d time, %s: RMSE %.5f, PSNR %.2f dB (made steps %.2f), "
                  "isosurface RMS %.3f voxel (p99 %.3f, %lld of %lld crossings; kept steps %.3f), normal RMS %.2f "
                  "degrees (p99 %.2f), flips %s, %.1f s",
                  options.field.c_str(), n, options.steps, options.scale, options.time_scale, spec.c_str(), row.rmse,
                  row.psnr, row.psnr_made, row.iso_rms, row.iso_p99, row.iso_crossings, row.iso_true_crossings,
                  row.iso_rms_kept, row.iso_normal_rms, row.iso_normal_p99, st.flips.summary().c_str(), row.seconds);
    log(line);
    rows.push_back(row);
    results[spec] = std::move(out);
  }
  if (!options.picture_dir.empty()) {
    const std::vector<const Volume*> columns = picture_columns(reference, results, options.picture_methods);
    const std::string stem = options.field + "-x" + std::to_string(options.scale) + "-t" +
                             std::to_string(options.time_scale);
    const int step = steps_out / 2;
    const std::filesystem::path dir(options.picture_dir);
    const std::string path = (dir / (stem + ".png")).string();
    write_image(path, compare_series_views(columns, step, {VolumeView::slice_xy}, 0.0, 1.0), SampleFormat::uint8);
    log("picture: " + path + " (output step " + std::to_string(step) + ")");
    IsoView iso;
    iso.level = field.iso_level;
    iso.zoom = 1.8;
    iso.size = 2 * N;
    std::vector<Volume> middle;
    for (const Volume* v : columns) middle.push_back(time_step(*v, step));
    std::vector<const Volume*> middle_columns;
    for (const Volume& v : middle) middle_columns.push_back(&v);
    const std::string iso_path = (dir / (stem + "-iso.png")).string();
    write_image(iso_path, compare_views(middle_columns, {VolumeView::isosurface}, 0.0, 1.0, iso), SampleFormat::uint8);
    log("picture: " + iso_path);
  }
  return rows;
}

std::string volume_series_experiment_table(const std::vector<VolumeSeriesExperimentRow>& rows) {
  std::string table =
      "| field | method | RMSE | PSNR (dB) | PSNR, made steps (dB) | isosurface RMS, made steps (voxels) | "
      "isosurface p99 | shading normal RMS, made steps (degrees) | normal p99 | crossings / true | simplices | "
      "flips | seconds |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    char line[400];
    if (r.method == reference_method)
      std::snprintf(line, sizeof line, "| %s | %s | 0 | — | — | %.3f | %.3f | %.2f | %.2f | %lld / %lld | | | |\n",
                    r.field.c_str(), r.method.c_str(), r.iso_rms, r.iso_p99, r.iso_normal_rms, r.iso_normal_p99,
                    r.iso_crossings, r.iso_true_crossings);
    else
      std::snprintf(line, sizeof line,
                    "| %s | %s | %.5f | %.2f | %.2f | %.3f | %.3f | %.2f | %.2f | %lld / %lld | %lld | %lld | %.1f |\n",
                    r.field.c_str(), r.method.c_str(), r.rmse, r.psnr, r.psnr_made, r.iso_rms, r.iso_p99,
                    r.iso_normal_rms, r.iso_normal_p99, r.iso_crossings, r.iso_true_crossings, r.simplices, r.flips,
                    r.seconds);
    table += line;
  }
  return table;
}

}  // namespace ddt
