#include "eval/evaluation.hpp"
#include "util/file_names.hpp"

#include "eval/classic_resize.hpp"
#include "core/costs.hpp"
#include "eval/edge_sharpness.hpp"
#include "util/error.hpp"
#include "util/text.hpp"
#include "io/image_io.hpp"
#include "eval/matlab_resize.hpp"
#include "eval/metrics.hpp"
#include "eval/peer_resize.hpp"
#include "io/safe_file.hpp"
#include "eval/synthetic_scenes.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <system_error>

namespace fs = std::filesystem;

namespace ddt {
namespace {

EvalMethod ddt_method(const std::string& name, const UpscaleOptions& options) {
  find_cost(options.cost);  // throws, naming the valid costs, before any work
  return {name, [options](const Image& lr, int w, int h) { return upscale(lr, w, h, options); }};
}

bool is_peer(const std::string& name) {
  const std::vector<std::string> peers = peer_methods();
  return std::find(peers.begin(), peers.end(), name) != peers.end();
}

EvalMethod classic_method(const std::string& name, const std::string& classic) {
  return {name, [classic](const Image& lr, int w, int h) { return classic_resize(lr, w, h, classic); }};
}

// The protocol works on colour or grey pictures; alpha is not part of the scores.
Image drop_alpha(const Image& img) {
  const int keep = img.channels >= 3 ? 3 : 1;
  if (keep == img.channels) return img;
  Image out(img.width, img.height, keep);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < keep; ++c) out.at(x, y, c) = img.at(x, y, c);
  return out;
}

// MATLAB modcrop: keep the top-left width - width % s by height - height % s.
Image crop_to_multiple(const Image& img, int s) {
  const int w = img.width - img.width % s, h = img.height - img.height % s;
  if (w == img.width && h == img.height) return img;
  Image out(w, h, img.channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < img.channels; ++c) out.at(x, y, c) = img.at(x, y, c);
  return out;
}

// Runs one method, timed, and checks what it returns.
Image run_timed(const EvalMethod& method, const Image& lr, int w, int h, double& seconds) {
  const auto start = std::chrono::steady_clock::now();
  Image sr = method.run(lr, w, h);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (sr.width != w || sr.height != h || sr.channels != lr.channels)
    throw Error("returned " + std::to_string(sr.width) + "x" + std::to_string(sr.height) + "x" +
                std::to_string(sr.channels) + " instead of " + std::to_string(w) + "x" + std::to_string(h) +
                "x" + std::to_string(lr.channels));
  return sr;
}

// Measures taken on SR beside the scores (synthetic mode).
using Measure = std::function<void(const Image& sr, EvalRow& row)>;

EvalRow score(const std::string& image, int s, const EvalMethod& method, const Image& lr, const Image& hr,
              bool quantize, const Measure& measure = {}) {
  EvalRow row{image, s, method.name};
  try {
    Image sr = run_timed(method, lr, hr.width, hr.height, row.seconds);
    if (quantize) sr = round_to_8bit(sr);
    row.psnr = psnr_y(sr, hr, s);
    row.ssim = ssim_y(sr, hr, s);
    if (measure) measure(sr, row);
  } catch (const std::exception& e) {
    throw Error(method.name + " on " + image + " x" + std::to_string(s) + ": " + e.what());
  }
  return row;
}

void check_scales(const std::vector<int>& scales) {
  if (scales.empty()) throw Error("no scale given");
  for (int s : scales)
    if (s < 2) throw Error("scale " + std::to_string(s) + " is not an integer >= 2");
}

void check_methods_given(const std::vector<EvalMethod>& methods) {
  if (methods.empty()) throw Error("no method given");
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

// The known edge of a step-edge scene in the pixel coordinates of a
// width x height rendering (the normal rescaled, then renormalized, so
// unequal sides keep it perpendicular).
StepEdge step_edge_in_pixels(const SceneStepEdge& e, int width, int height) {
  const double nx = e.nx / width, ny = e.ny / height, norm = std::hypot(nx, ny);
  return {e.x * width, e.y * height, nx / norm, ny / norm, e.low, e.high};
}

// The synthetic measures of one scene at scale s against its HR rendering.
Measure synthetic_measures(const Scene& scene, const Image& hr, int s) {
  return [&scene, &hr, s](const Image& sr, EvalRow& row) {
    TruthHaloOptions halo;
    halo.shave = s;  // the border the scores shave too
    row.halo = 100.0 * truth_halo(sr, hr, s, halo);
    if (!scene.step_edge) return;
    const EdgeSharpness e = measure_edge_sharpness(sr, step_edge_in_pixels(*scene.step_edge, sr.width, sr.height), s);
    row.rise_width = e.rise_width;
    row.wobble = e.wobble;
    row.edge_offset = e.offset;
    row.overshoot = e.overshoot;
  };
}

std::string number(double v) {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", v);
  return buf;
}

}  // namespace

std::vector<std::string> eval_method_names() {
  return {"ddt", "ddt-<cost>", "ddt-linear", "ddt-linear-<cost>", "delaunay", "delaunay-cubic",
          "bicubic", "bicubic-oiio", "lanczos", "bilinear", "nearest", "opencv-lanczos4", "opencv-cubic",
          "vips-nohalo"};
}

std::vector<EvalMethod> make_eval_methods(const std::vector<std::string>& names,
                                          const std::vector<std::string>& ddt_costs,
                                          const UpscaleOptions& ddt_options) {
  std::vector<EvalMethod> methods;
  auto add = [&](EvalMethod m) {
    for (const auto& existing : methods)
      if (existing.name == m.name) throw Error("method '" + m.name + "' is given twice");
    methods.push_back(std::move(m));
  };
  for (const auto& name : names) {
    // ddt[-<render>][-<cost>] and delaunay[-<render>]: render is cubic (the
    // default) or linear (the paper's surface).
    std::string rest = name;
    UpscaleOptions o = ddt_options;
    const bool is_ddt = rest == "ddt" || rest.rfind("ddt-", 0) == 0;
    const bool is_delaunay = rest == "delaunay" || rest.rfind("delaunay-", 0) == 0;
    if (is_ddt || is_delaunay) {
      rest = rest.substr(is_ddt ? 3 : 8);
      for (const Render render : {Render::linear, Render::cubic}) {
        const std::string suffix = std::string("-") + to_string(render);
        if (rest == suffix || rest.rfind(suffix + "-", 0) == 0) {
          o.render = render;
          rest = rest.substr(suffix.size());
        }
      }
      if (is_delaunay) {
        if (!rest.empty()) throw Error("unknown method '" + name + "' (delaunay takes -linear or -cubic)");
        o.optimize = false;
        add(ddt_method(name, o));
      } else if (!rest.empty()) {
        o.cost = rest.substr(1);
        add(ddt_method(name, o));
      } else if (ddt_costs.empty()) {
        add(ddt_method(name, o));
      } else {
        for (const auto& cost : ddt_costs) {
          UpscaleOptions oc = o;
          oc.cost = cost;
          add(ddt_method(name + "-" + cost, oc));
        }
      }
    } else if (name == "bicubic") {
      // The protocol's reference bicubic, not OIIO's: the published rows were made with MATLAB.
      add({name, [](const Image& lr, int w, int h) { return matlab_imresize_bicubic(lr, w, h); }});
    } else if (name == "bicubic-oiio") {
      add(classic_method(name, "bicubic"));
    } else if (name == "lanczos" || name == "bilinear" || name == "nearest") {
      add(classic_method(name, name));
    } else if (is_peer(name)) {
      add({name, [name](const Image& lr, int w, int h) { return peer_resize(lr, w, h, name); }});
    } else {
      throw Error("unknown method '" + name + "' (valid: " + joined(eval_method_names()) + ")");
    }
  }
  return methods;
}

void check_eval_methods(const std::vector<EvalMethod>& methods) {
  // A smooth 4x4 colour patch: big enough for a triangulation, tiny enough to be instant.
  Image probe(4, 4, 3);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 3; ++c) probe.at(x, y, c) = static_cast<float>((x + 2 * y + c) % 7) / 7.0f;
  for (const auto& m : methods) {
    try {
      double seconds = 0;
      run_timed(m, probe, 8, 8, seconds);
    } catch (const std::exception& e) {
      throw Error(m.name + ": " + e.what());
    }
  }
}

std::vector<std::string> list_images(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("'" + dir + "' is not a directory");
  std::vector<std::string> files;
  fs::directory_iterator it(dir, ec);
  if (ec) throw Error("cannot list '" + dir + "': " + ec.message());
  for (const auto& entry : it) {
    if (!entry.is_regular_file(ec)) continue;
    const std::string ext = lower_extension(entry.path().string());
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tif" || ext == ".tiff")
      files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
    return fs::path(a).filename().string() < fs::path(b).filename().string();
  });
  return files;
}

std::vector<EvalRow> evaluate_image(const std::string& name, const Image& hr_in,
                                    const std::vector<int>& scales,
                                    const std::vector<EvalMethod>& methods) {
  check_scales(scales);
  check_methods_given(methods);
  const Image hr_full = drop_alpha(hr_in);
  std::vector<EvalRow> rows;
  for (int s : scales) {
    if (hr_full.width < s || hr_full.height < s)
      throw Error(name + ": " + std::to_string(hr_full.width) + "x" + std::to_string(hr_full.height) +
                  " is smaller than the scale " + std::to_string(s));
    const Image hr = crop_to_multiple(hr_full, s);
    const Image lr = round_to_8bit(matlab_imresize_bicubic(hr, hr.width / s, hr.height / s));
    for (const auto& m : methods) rows.push_back(score(name, s, m, lr, hr, /*quantize=*/true));
  }
  return rows;
}

std::vector<EvalRow> evaluate_set(const std::string& dir, const EvalOptions& options) {
  check_scales(options.scales);
  check_methods_given(options.methods);
  const std::vector<std::string> files = list_images(dir);
  if (files.empty()) throw Error("'" + dir + "' holds no PNG, JPEG, BMP or TIFF image");
  check_eval_methods(options.methods);
  std::vector<EvalRow> rows;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string name = fs::path(files[i]).filename().string();
    if (options.progress) options.progress(name, static_cast<int>(i), static_cast<int>(files.size()));
    const ImageFile file = read_image(files[i]);
    std::vector<EvalRow> image_rows = evaluate_image(name, file.image, options.scales, options.methods);
    if (options.on_image) options.on_image(image_rows);
    rows.insert(rows.end(), image_rows.begin(), image_rows.end());
  }
  return rows;
}

std::vector<EvalRow> evaluate_synthetic(const EvalOptions& options) {
  check_scales(options.scales);
  check_methods_given(options.methods);
  if (options.synthetic_size < 1) throw Error("synthetic size must be >= 1");
  check_eval_methods(options.methods);
  const std::vector<Scene> scenes = standard_scenes();
  const int w = options.synthetic_size, h = options.synthetic_size;
  std::vector<EvalRow> rows;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const Scene& scene = scenes[i];
    if (options.progress) options.progress(scene.name, static_cast<int>(i), static_cast<int>(scenes.size()));
    std::vector<EvalRow> scene_rows;
    const Image lr = render_scene(scene, w, h);
    for (int s : options.scales) {
      const Image hr = render_scene(scene, w * s, h * s);
      // Both renderings are exact box filters of one scene: nothing to quantize away.
      const Measure measure = synthetic_measures(scene, hr, s);
      for (const auto& m : options.methods)
        scene_rows.push_back(score(scene.name, s, m, lr, hr, /*quantize=*/false, measure));
    }
    if (options.on_image) options.on_image(scene_rows);
    rows.insert(rows.end(), scene_rows.begin(), scene_rows.end());
  }
  return rows;
}

std::vector<EvalMean> mean_by_method_and_scale(const std::vector<EvalRow>& rows) {
  std::vector<std::string> method_order;
  std::vector<int> scale_order;
  for (const auto& r : rows) {
    if (std::find(method_order.begin(), method_order.end(), r.method) == method_order.end())
      method_order.push_back(r.method);
    if (std::find(scale_order.begin(), scale_order.end(), r.scale) == scale_order.end())
      scale_order.push_back(r.scale);
  }
  std::sort(scale_order.begin(), scale_order.end());
  std::vector<EvalMean> means;
  for (int s : scale_order) {
    for (const auto& m : method_order) {
      EvalMean mean{m, s};
      for (const auto& r : rows) {
        if (r.scale != s || r.method != m) continue;
        ++mean.images;
        mean.psnr += r.psnr;
        mean.ssim += r.ssim;
        mean.seconds += r.seconds;
      }
      if (mean.images == 0) continue;
      mean.psnr /= mean.images;
      mean.ssim /= mean.images;
      mean.seconds /= mean.images;
      means.push_back(mean);
    }
  }
  return means;
}

std::vector<EvalEdgeSummary> edge_summary_by_method_and_scale(const std::vector<EvalRow>& rows) {
  std::vector<EvalEdgeSummary> summaries;
  for (const EvalMean& mean : mean_by_method_and_scale(rows)) {
    EvalEdgeSummary e{mean.method, mean.scale};
    for (const auto& r : rows) {
      if (r.scale != e.scale || r.method != e.method || std::isnan(r.rise_width)) continue;
      ++e.edges;
      e.rise_width += r.rise_width;
      e.rise_width_max = std::max(e.rise_width_max, r.rise_width);
      e.wobble += r.wobble;
      e.wobble_max = std::max(e.wobble_max, r.wobble);
      e.overshoot_max = std::max(e.overshoot_max, r.overshoot);
      if (!std::isnan(r.halo)) e.halo_max = std::max(e.halo_max, r.halo);
    }
    if (e.edges == 0) continue;
    e.rise_width /= e.edges;
    e.wobble /= e.edges;
    summaries.push_back(e);
  }
  return summaries;
}

void write_eval_csv(const std::string& path, const std::vector<EvalRow>& rows, bool synthetic_columns) {
  if (path.empty()) throw Error("no CSV file given");
  std::ostringstream out;
  out << "image,scale,method,psnr,ssim,seconds";
  if (synthetic_columns) out << ",halo,rise_width,wobble,edge_offset,overshoot";
  out << '\n';
  for (const auto& r : rows) {
    out << csv_field(r.image) << ',' << r.scale << ',' << csv_field(r.method) << ',' << number(r.psnr) << ','
        << number(r.ssim) << ',' << number(r.seconds);
    if (synthetic_columns)
      out << ',' << number(r.halo) << ',' << number(r.rise_width) << ',' << number(r.wobble) << ','
          << number(r.edge_offset) << ',' << number(r.overshoot);
    out << '\n';
  }
  // Staged in a private directory beside the target, checked, renamed (safe_file.hpp).
  write_file_atomically(path, out.str());
}

}  // namespace ddt
