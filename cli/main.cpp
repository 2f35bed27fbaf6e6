// ddtscale — enlarge images by data-dependent triangulation.
//   ddtscale in.png out.exr --scale 10
//   ddtscale eval --set DIR ...      (see `ddtscale eval --help`)

#include "batch.hpp"
#include "commands.hpp"
#include "upscale_arguments.hpp"

#include "eval/classic_resize.hpp"
#include "eval/comparison.hpp"
#include "core/costs.hpp"
#include "util/allocator_tuning.hpp"
#include "util/error.hpp"
#include "io/image_io.hpp"
#include "image/image_mesh.hpp"
#include "image/mesh_view.hpp"
#include "util/progress.hpp"
#include "util/size_limits.hpp"
#include "pipeline/file_upscale.hpp"
#include "pipeline/upscale.hpp"
#include "util/thread_limit.hpp"
#include "util/timing.hpp"

#include <CGAL/version.h>
#include <OpenImageIO/imageio.h>
#include <oneapi/tbb/version.h>


#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <memory>

#include <unistd.h>

namespace {

using ddt::seconds_since;

// Runs the job `args` (validate_arguments passed); returns the exit status.
int run_upscale_job(UpscaleArguments args) {
  try {
    ddt::check_output_path(args.output, args.input);
    ddt::PixelRegion roi;
    if (!args.mesh_roi.empty()) roi = ddt::parse_region(args.mesh_roi);
    if (!args.mesh_view.empty()) {
      const bool svg = args.mesh_view.size() > 4 && args.mesh_view.substr(args.mesh_view.size() - 4) == ".svg";
      ddt::check_output_path(args.mesh_view, args.input, !svg);
    }
    // Both cores unless --threads says otherwise (TBB for our stages, OIIO's pool for reading and writing).
    args.threads = ddt::usable_threads(args.threads);
    const auto thread_limit = ddt::limit_threads(args.threads);
    if (args.threads > 0) {
      OIIO::attribute("threads", args.threads);
      OIIO::attribute("exr_threads", args.threads);  // OpenEXR compresses blocks of rows in parallel
    }
    // A progress bar on a terminal for runs over a second, unless --quiet.
    ddt::Progress progress;
    // The bar draws on its own copy of the terminal's descriptor: image I/O
    // points stderr at /dev/null while libraries read and write
    // (src/io/image_io.cpp), and the bar goes on through the write stage.
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> bar_out(nullptr, &std::fclose);
    std::unique_ptr<ddt::ProgressBar> bar;
    if (!args.quiet && ddt::ProgressBar::is_terminal(stderr)) {
      const int terminal = ::dup(STDERR_FILENO);
      if (terminal >= 0) bar_out.reset(::fdopen(terminal, "w"));
      if (terminal >= 0 && !bar_out) ::close(terminal);
      if (bar_out) {
        std::setvbuf(bar_out.get(), nullptr, _IONBF, 0);
        bar = std::make_unique<ddt::ProgressBar>(progress, bar_out.get());
      }
    }
    auto log = [&](const std::string& line) {
      if (!args.verbose) return;
      if (bar) bar->print(line);
      else std::cerr << line << "\n";
    };
    ddt::UpscaleOptions options = upscale_options(args);
    if (args.verbose) options.log = log;
    options.progress = &progress;
    const ddt::SizeRequest size = size_request(args);
    if (args.compare.empty() && args.mesh_view.empty()) {
      ddt::FileUpscaleJob job{args.input, args.output, size, options, args.writing.encode, !args.writing.no_stream,
                              args.max_input_pixels, {}};
      if (!args.quiet) job.warn = [](const std::string& line) { std::cerr << "ddtscale: warning: " << line << "\n"; };
      const ddt::FileUpscaleResult result = ddt::upscale_file(std::move(job));
      if (bar) bar->stop();
      if (!args.quiet && !args.verbose) std::cerr << args.output << ": " << result.width << "x" << result.height << "\n";
      return 0;
    }
    // --compare and --mesh-view need the whole input and output.
    progress.begin("read");
    auto t0 = std::chrono::steady_clock::now();
    int out_w = 0, out_h = 0, compare_gap = 0;
    ddt::ImageReadLimits limits;
    limits.max_pixels = args.max_input_pixels;
    limits.check = [&](const ddt::ImageHeader& header) {
      ddt::output_size(size, header.width, header.height, out_w, out_h);
      compare_gap = std::max(2, out_w / 256);
      const int written_w = args.compare.empty() ? out_w : 2 * out_w + compare_gap;
      ddt::check_image_writable(args.output, written_w, out_h, header.channels, header.format, header.alpha_channel,
                                args.writing.encode);
      if (!args.mesh_view.empty()) ddt::check_region(roi, header.width, header.height);
      ddt::check_memory_fits("this job", ddt::upscale_job_bytes(header.width, header.height, header.channels, out_w,
                                                                out_h, options, false, args.compare.empty() ? 1 : 4));
    };
    ddt::ImageFile file = ddt::read_image(args.input, limits);
    log("read: " + args.input + ", " + std::to_string(file.image.width) + "x" + std::to_string(file.image.height) +
        "x" + std::to_string(file.image.channels) + ", " + std::to_string(seconds_since(t0)) + " s");
    if (file.pages > 1 && !args.quiet) std::cerr << "ddtscale: warning: " << ddt::pages_warning(args.input, file.pages) << "\n";
    options.alpha_channel = file.alpha_channel;
    const OIIO::ParamValueList metadata = ddt::scaled_metadata(
        file.metadata, double(out_w) / file.image.width, double(out_h) / file.image.height);
    ddt::UpscaleStats stats;
    ddt::Image out = ddt::upscale(file.image, out_w, out_h, options, &stats);
    if (!args.compare.empty()) {
      t0 = std::chrono::steady_clock::now();
      const ddt::Image classic = ddt::classic_resize(file.image, out_w, out_h, args.compare);
      out = ddt::side_by_side(classic, out, compare_gap, 0.0f, file.alpha_channel);
      log("compare: " + args.compare + " | ddt, " + std::to_string(seconds_since(t0)) + " s");
    }
    if (!args.mesh_view.empty()) {
      t0 = std::chrono::steady_clock::now();
      const int w = file.image.width, h = file.image.height;
      if (args.mesh_roi.empty() && (w > 256 || h > 256))
        roi = {std::max(0, w / 2 - 64), std::max(0, h / 2 - 64), std::min(w, 128), std::min(h, 128)};
      ddt::UpscaleOptions plain = options;
      plain.optimize = false;
      plain.log = nullptr;
      options.log = nullptr;
      const ddt::Mesh2 initial = ddt::image_mesh(file.image, plain);
      const ddt::Mesh2 optimized = ddt::image_mesh(file.image, options);
      ddt::write_mesh_view(args.mesh_view, optimized, &initial, file.image, roi);
      log("mesh: " + args.mesh_view + ", " + std::to_string(seconds_since(t0)) + " s");
    }
    t0 = std::chrono::steady_clock::now();
    progress.begin("write");
    ddt::write_image(args.output, out, file.format, file.alpha_channel, &metadata, args.writing.encode);
    log("write: " + args.output + ", " + std::to_string(seconds_since(t0)) + " s");
    if (bar) bar->stop();
    if (!args.quiet && !args.verbose)
      std::cerr << args.output << ": " << out.width << "x" << out.height << "\n";  // as written (--compare: both halves)
    return 0;
  } catch (const ddt::Error& e) {
    std::cerr << "ddtscale: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "ddtscale: out of memory (try a smaller output or --max-pixels)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "ddtscale: " << e.what() << "\n";
    return 1;
  }
}

int run_upscale(int argc, char** argv) {
  const UpscaleCommandLine line = parse_upscale_command_line(argc, argv);
  switch (line.action) {
    case UpscaleCommandLine::Action::help:
      std::cout << line.text;
      return 0;
    case UpscaleCommandLine::Action::list_costs:
      for (const auto& c : ddt::cost_functions()) std::cout << c.name << "\n";
      return 0;
    case UpscaleCommandLine::Action::version:
      std::cout << "ddtscale " << DDTSCALE_VERSION << " (OpenImageIO " << OIIO_VERSION_STRING << ", CGAL "
                << CGAL_VERSION_STR << ", TBB " << TBB_VERSION_MAJOR << "." << TBB_VERSION_MINOR << ")\n";
      return 0;
    case UpscaleCommandLine::Action::usage_error:
      std::cerr << "ddtscale: " << line.text << "\n";
      return 2;
    case UpscaleCommandLine::Action::batch:
      return run_batch(line.forwarded, line.batch_inputs, line.batch, line.args.quiet);
    case UpscaleCommandLine::Action::run:
      break;
  }
  try {
    validate_arguments(line.args);
  } catch (const ddt::Error& e) {
    std::cerr << "ddtscale: " << e.what() << "\n";
    return 1;
  }
  return run_upscale_job(line.args);
}

}  // namespace

int main(int argc, char** argv) {
  // Volumes and sequences allocate tiles of changing sizes: under the image
  // command's setting their heap grew with each tile (docs/performance.md).
  ddt::tune_allocator(ddt::AllocatorUse::general);
  if (argc >= 2 && std::strcmp(argv[1], "eval") == 0) return run_eval_command(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "grid") == 0) return run_grid_command(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "scene") == 0) return run_scene_command(argc - 1, argv + 1);
  if (is_volume_command(argc, argv)) return run_volume_command(argc, argv);
  if (is_sequence_command(argc, argv)) return run_sequence_command(argc, argv);
  ddt::tune_allocator(ddt::AllocatorUse::equal_bands);
  return run_upscale(argc, argv);
}
