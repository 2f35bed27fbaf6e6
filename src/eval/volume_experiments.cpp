#include "eval/volume_experiments.hpp"

#include "util/error.hpp"
#include "io/image_io.hpp"
#include "eval/volume_fields.hpp"
#include "eval/volume_pictures.hpp"
#include "volume/volume_upscale.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

namespace ddt {
VolumeUpscaleOptions volume_options_for(const std::string& spec) {
  VolumeUpscaleOptions o;
  const auto colon = spec.find(':');
  std::string name = spec.substr(0, colon);
  if (colon != std::string::npos) o.cost = spec.substr(colon + 1);
  for (const Render render : {Render::linear, Render::cubic}) {
    const std::string suffix = std::string("-") + to_string(render);
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0 &&
        (name.rfind("ddt", 0) == 0 || name.rfind("delaunay", 0) == 0)) {
      name.resize(name.size() - suffix.size());
      o.render = render;
    }
  }
  o.method = volume_method_by_name(name);
  return o;
}

std::vector<VolumeExperimentRow> run_volume_experiments(const VolumeExperimentOptions& options) {
  if (options.size < 2 || options.scale < 1) throw Error("volume experiments: size must be >= 2 and scale >= 1");
  if (options.quantize_bits < 0 || options.quantize_bits > 24)
    throw Error("volume experiments: quantize to 1..24 bits (0: no quantization)");
  const std::string suffix = options.quantize_bits > 0 ? "-q" + std::to_string(options.quantize_bits) : "";
  for (const auto& spec : options.methods) find_cost(volume_options_for(spec).cost);  // fail fast
  if (!options.picture_dir.empty() && !std::filesystem::is_directory(options.picture_dir))
    throw Error("picture directory '" + options.picture_dir + "' does not exist");
  auto log = [&](const std::string& line) {
    if (options.log) options.log(line);
  };
  std::vector<VolumeExperimentRow> rows;
  const int n = options.size, N = options.size * options.scale;
  for (const std::string& name : options.fields) {
    const VolumeField& field = find_volume_field(name);
    Volume input = sample_field(field, n, n, n, options.input_ss);
    if (options.quantize_bits > 0) {
      const double levels = std::ldexp(1.0, options.quantize_bits) - 1;
      for (float& v : input.voxels) v = static_cast<float>(std::round(std::clamp(double(v), 0.0, 1.0) * levels) / levels);
    }
    const Volume reference = sample_field(field, N, N, N, options.reference_ss);
    std::map<std::string, Volume> results;
    for (const std::string& spec : options.methods) {
      const VolumeUpscaleOptions o = volume_options_for(spec);
      VolumeUpscaleStats st;
      const auto t0 = std::chrono::steady_clock::now();
      Volume out = upscale_volume(input, N, N, N, o, &st);
      VolumeExperimentRow row;
      row.field = name;
      row.method = spec;
      row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      row.rmse = volume_rmse(out, reference);
      row.psnr = volume_psnr(out, reference, 1.0);
      row.flips = st.flips.total();
      char line[300];
      std::snprintf(line, sizeof line, "%s %d^3 x%d, %s: RMSE %.5f, PSNR %.2f dB, flips %s, %.2f s", name.c_str(), n,
                    options.scale, spec.c_str(), row.rmse, row.psnr, st.flips.summary().c_str(), row.seconds);
      log(line);
      rows.push_back(row);
      results[spec] = std::move(out);
    }
    if (!options.picture_dir.empty()) {
      const std::vector<const Volume*> columns = picture_columns(reference, results, options.picture_methods);
      const Image picture =
          compare_views(columns, {VolumeView::slice_xy, VolumeView::slice_xz, VolumeView::mip_z}, 0.0, 1.0);
      const std::string path =
          (std::filesystem::path(options.picture_dir) / (name + "-x" + std::to_string(options.scale) + suffix + ".png")).string();
      write_image(path, picture, SampleFormat::uint8);
      log("picture: " + path);
      IsoView iso;
      iso.level = options.iso_level > 0 ? options.iso_level : field.iso_level;
      iso.zoom = 1.8;
      iso.size = 2 * N;
      const std::string iso_path = (std::filesystem::path(options.picture_dir) /
                                    (name + "-x" + std::to_string(options.scale) + suffix + "-iso.png")).string();
      write_image(iso_path, compare_views(columns, {VolumeView::isosurface}, 0.0, 1.0, iso), SampleFormat::uint8);
      log("picture: " + iso_path);
    }
  }
  return rows;
}

std::string volume_experiment_table(const std::vector<VolumeExperimentRow>& rows) {
  std::string table = "| field | method | RMSE | PSNR (dB) | flips | seconds |\n|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    char line[300];
    std::snprintf(line, sizeof line, "| %s | %s | %.5f | %.2f | %lld | %.2f |\n", r.field.c_str(), r.method.c_str(),
                  r.rmse, r.psnr, r.flips, r.seconds);
    table += line;
  }
  return table;
}

}  // namespace ddt
