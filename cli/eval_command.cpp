// `ddtscale eval` — runs the evaluation protocol of evaluation.hpp and
// prints one table per image, then the means per scale and method.

#include "command_line.hpp"
#include "commands.hpp"
#include "whole_number.hpp"

#include "core/costs.hpp"
#include "util/error.hpp"
#include "eval/evaluation.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace {

void print_table_header(bool synthetic = false) {
  std::printf("  %5s  %-18s %9s %8s %10s", "scale", "method", "PSNR", "SSIM", "seconds");
  if (synthetic) std::printf(" %7s %7s %7s %7s %7s", "halo%", "rise", "wobble", "offset", "over%");
  std::printf("\n");
}

void print_table_row(int scale, const std::string& method, double psnr, double ssim, double seconds) {
  std::printf("  %5s  %-18s %9.4f %8.4f %10.5f", ("x" + std::to_string(scale)).c_str(), method.c_str(), psnr,
              ssim, seconds);
}

// A measure not taken (NaN) prints as blanks.
void print_measure(double v, int decimals) {
  if (std::isnan(v)) std::printf(" %7s", "");
  else std::printf(" %7.*f", decimals, v);
}

void print_synthetic_measures(const ddt::EvalRow& r) {
  print_measure(r.halo, 2);
  print_measure(r.rise_width, 3);
  print_measure(r.wobble, 3);
  print_measure(r.edge_offset, 3);
  print_measure(r.overshoot, 2);
}

// The straight step edges, per method and scale: mean and worst over the angles.
void print_edge_summary(const std::vector<ddt::EvalEdgeSummary>& summaries) {
  if (summaries.empty()) return;
  std::printf("\nedge sharpness over %d step edges (input pixels; overshoot and halo in %% of the step)\n",
              summaries.front().edges);
  std::printf("  %5s  %-18s %9s %9s %9s %9s %9s %9s\n", "scale", "method", "rise", "rise max", "wobble",
              "wob. max", "over% max", "halo% max");
  for (const auto& e : summaries)
    std::printf("  %5s  %-18s %9.3f %9.3f %9.4f %9.4f %9.2f %9.2f\n", ("x" + std::to_string(e.scale)).c_str(),
                e.method.c_str(), e.rise_width, e.rise_width_max, e.wobble, e.wobble_max, e.overshoot_max,
                e.halo_max);
}

// Exit statuses: 2 for bad arguments, 1 when the work fails (a missing set,
// a corrupt image, an unwritable CSV).
int fail(const std::string& message, int status) {
  std::fprintf(stderr, "ddtscale eval: error: %s\n", one_line(message).c_str());
  return status;
}

// A CSV that cannot be written should stop the run before the work, not after it.
void check_csv_path(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw ddt::Error("--csv '" + path + "' is a directory");
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) throw ddt::Error("--csv: directory '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0) throw ddt::Error("--csv: directory '" + dir.string() + "' is not writable");
}

}  // namespace

int run_eval_command(int argc, char** argv) {
  CLI::App app{
      "Score upscalers with the single-image super-resolution protocol: HR cropped to a multiple of\n"
      "the scale, LR = MATLAB bicubic downscale rounded to 8 bits, SR = method(LR) rounded to 8 bits,\n"
      "PSNR and SSIM on BT.601 luma with the scale shaved from each border. --synthetic scores against\n"
      "analytic scenes rendered at both resolutions instead, and adds the truth-based halo (halo%: how far\n"
      "the output leaves the true scene's range within one input pixel, % of the scene's step) and, on the\n"
      "straight step edges, the 10-90 % rise width, the RMS wobble and mean offset of the 50 % contour\n"
      "from the true line (input pixels) and the overshoot (over%, % of the step)."};
  app.name("ddtscale eval");

  std::string set_dir, csv_path;
  std::vector<int> scales{2, 3, 4};
  std::vector<std::string> methods{"ddt", "bicubic", "lanczos", "bilinear", "nearest"};
  std::vector<std::string> costs;
  bool synthetic = false, quiet = false, luma_cost = false;
  int size = 64;

  auto* set_option = app.add_option("--set", set_dir, "Directory of ground-truth images (PNG, JPEG, BMP, TIFF)");
  app.add_option("--scale", scales, "Integer scales, comma-separated")
      ->delimiter(',')
      ->check(whole_number(2, 100))
      ->capture_default_str();
  std::string method_help = "Methods, comma-separated:";
  for (const auto& name : ddt::eval_method_names()) method_help += " " + name;
  app.add_option("--methods", methods, method_help)->delimiter(',')->capture_default_str();
  app.add_option("--cost", costs,
                 "DDT costs, comma-separated; 'ddt' becomes one method ddt-<cost> per cost (" +
                     ddt::cost_names_joined() + ")")
      ->delimiter(',');
  app.add_flag("--luma-cost", luma_cost, "DDT flips decided on luminance only");
  const ddt::UpscaleOptions defaults;
  std::string slopes = ddt::to_string(defaults.slopes);
  std::string model = ddt::to_string(defaults.model);
  app.add_option("--model", model, "acquisition model of the ddt methods: box, gauss:SIGMA, bicubic, point")
      ->capture_default_str();
  bool no_step_edges = false;
  app.add_flag("--no-step-edges", no_step_edges, "ddt methods under the box model: no straight-edge footprints");
  app.add_option("--slopes", slopes, "slope limiter of the cubic render: mc4, mc, central, minmod")
      ->check(CLI::IsMember(ddt::slope_limiter_names()))
      ->capture_default_str();
  std::string optimizer = ddt::to_string(defaults.optimizer);
  std::uint64_t seed = defaults.anneal.seed;
  app.add_option("--optimizer", optimizer, "DDT optimizer of every ddt method: lawson, anneal or lookahead")
      ->check(CLI::IsMember(ddt::optimizer_names()))
      ->capture_default_str();
  app.add_option("--seed", seed, "seed of --optimizer anneal")->check(whole_number(0))->capture_default_str();
  app.add_option("--csv", csv_path,
                 "Write every score to this CSV file: image,scale,method,psnr,ssim,seconds (--synthetic adds "
                 "halo,rise_width,wobble,edge_offset,overshoot)");
  auto* synthetic_flag = app.add_flag("--synthetic", synthetic, "Score on the analytic scenes instead of a set");
  app.add_option("--size", size, "Width and height of the synthetic LR renderings")
      ->check(whole_number(1, 4096))
      ->capture_default_str();
  app.add_flag("--quiet", quiet, "No progress lines on stderr");
  set_option->excludes(synthetic_flag);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    return fail(e.what(), 2);
  }

  ddt::EvalOptions options;
  try {
    if (!synthetic && set_dir.empty()) throw ddt::Error("give --set DIR or --synthetic");
    ddt::UpscaleOptions ddt_options;
    ddt_options.luma_cost = luma_cost;
    ddt_options.slopes = ddt::slope_limiter_by_name(slopes);
    ddt_options.model = ddt::parse_acquisition_model(model);
    ddt_options.step_edges = !no_step_edges;
    ddt_options.optimizer = ddt::optimizer_by_name(optimizer);
    ddt_options.anneal.seed = seed;
    options.scales = scales;
    options.methods = ddt::make_eval_methods(methods, costs, ddt_options);
    options.synthetic_size = size;
  } catch (const std::exception& e) {
    return fail(e.what(), 2);
  }

  try {
    if (!csv_path.empty()) check_csv_path(csv_path);
    if (!quiet)
      options.progress = [](const std::string& name, int index, int count) {
        std::fprintf(stderr, "eval: [%d/%d] %s\n", index + 1, count, name.c_str());
      };
    options.on_image = [synthetic](const std::vector<ddt::EvalRow>& rows) {
      if (rows.empty()) return;
      std::printf("%s\n", rows.front().image.c_str());
      print_table_header(synthetic);
      for (const auto& r : rows) {
        print_table_row(r.scale, r.method, r.psnr, r.ssim, r.seconds);
        if (synthetic) print_synthetic_measures(r);
        std::printf("\n");
      }
      std::printf("\n");
      std::fflush(stdout);
    };

    const std::vector<ddt::EvalRow> rows =
        synthetic ? ddt::evaluate_synthetic(options) : ddt::evaluate_set(set_dir, options);

    const auto means = ddt::mean_by_method_and_scale(rows);
    const int images = means.empty() ? 0 : means.front().images;
    const std::string over = synthetic ? " scenes" : " images of " + set_dir;
    std::printf("mean over %d%s\n", images, over.c_str());
    print_table_header();
    for (const auto& m : means) {
      print_table_row(m.scale, m.method, m.psnr, m.ssim, m.seconds);
      std::printf("\n");
    }
    if (synthetic) print_edge_summary(ddt::edge_summary_by_method_and_scale(rows));
    std::fflush(stdout);

    if (!csv_path.empty()) ddt::write_eval_csv(csv_path, rows, synthetic);
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
  return 0;
}
