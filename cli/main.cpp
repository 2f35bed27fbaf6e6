// ddtscale — enlarge images by data-dependent triangulation.
//   ddtscale in.png out.exr --scale 10
//   ddtscale eval --set DIR ...      (see `ddtscale eval --help`)

#include "batch.hpp"
#include "commands.hpp"
#include "file_job.hpp"
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
  // OpenImageIO's pool reads and writes; OpenEXR compresses blocks of rows in parallel.
  if (const int threads = ddt::usable_threads(args.threads); threads > 0) {
    OIIO::attribute("threads", threads);
    OIIO::attribute("exr_threads", threads);
  }
  if (args.compare.empty() && args.mesh_view.empty()) return run_file_job(std::move(args));
  // --compare and --mesh-view need the whole input and output.
  return report_failure([&] {
    ddt::check_output_path(args.output, args.input);
    ddt::PixelRegion roi;
    if (!args.mesh_roi.empty()) roi = ddt::parse_region(args.mesh_roi);
    if (!args.mesh_view.empty()) {
      const bool svg = args.mesh_view.size() > 4 && args.mesh_view.substr(args.mesh_view.size() - 4) == ".svg";
      ddt::check_output_path(args.mesh_view, args.input, !svg);
    }
    args.threads = ddt::usable_threads(args.threads);
    const auto thread_limit = ddt::limit_threads(args.threads);
    JobConsole console(args.quiet, args.verbose);
    auto log = [&console](const std::string& line) { console.log(line); };
    ddt::UpscaleOptions options = upscale_options(args);
    if (args.verbose) options.log = log;
    options.progress = &console.progress();
    const ddt::SizeRequest size = size_request(args);
    console.progress().begin("read");
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
    console.progress().begin("write");
    ddt::write_image(args.output, out, file.format, file.alpha_channel, &metadata, args.writing.encode);
    log("write: " + args.output + ", " + std::to_string(seconds_since(t0)) + " s");
    console.stop();
    if (!args.quiet && !args.verbose)
      std::cerr << args.output << ": " << out.width << "x" << out.height << "\n";  // as written (--compare: both halves)
    return 0;
  });
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
