// ddtscale — enlarge images by data-dependent triangulation.
//   ddtscale in.png out.exr --scale 10
//   ddtscale eval --set DIR ...      (see `ddtscale eval --help`)

#include "batch.hpp"
#include "commands.hpp"
#include "upscale_arguments.hpp"

#include "eval/classic_resize.hpp"
#include "eval/comparison.hpp"
#include "core/costs.hpp"
#include "io/band_writer.hpp"
#include "util/error.hpp"
#include "io/image_io.hpp"
#include "image/image_mesh.hpp"
#include "image/mesh_view.hpp"
#include "util/progress.hpp"
#include "util/size_limits.hpp"
#include "pipeline/banded_upscale.hpp"
#include "pipeline/upscale.hpp"
#include "util/thread_limit.hpp"
#include "util/timing.hpp"

#include <OpenImageIO/imageio.h>

#include <malloc.h>

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

ddt::UpscaleOptions upscale_options(const UpscaleArguments& args) {
  ddt::UpscaleOptions options;
  options.cost = args.cost;
  options.luma_cost = args.cost_channel == "luma";
  options.optimize = !args.no_optimize;
  options.render = ddt::render_by_name(args.render);
  options.slopes = ddt::slope_limiter_by_name(args.slopes);
  options.model = ddt::parse_acquisition_model(args.model);
  options.step_edges = !args.no_step_edges;
  options.relative_tolerance = args.tolerance;
  options.optimizer = ddt::optimizer_by_name(args.optimizer);
  options.anneal = args.anneal;
  options.tile_rows = args.tile_rows;
  return options;
}

// The job read, enlarged and written by bands of rows
// (pipeline/banded_upscale.hpp): the input is never decoded whole nor the
// output held whole.
int run_banded_job(const UpscaleArguments& args, ddt::ImageRowReader& reader, int out_w, int out_h,
                   ddt::UpscaleOptions options, ddt::Progress& progress, ddt::ProgressBar* bar,
                   const std::function<void(const std::string&)>& log) {
  const ddt::ImageHeader& header = reader.header();
  const ddt::ImageFile& file = reader.file();
  if (file.pages > 1 && !args.quiet)
    std::cerr << "ddtscale: warning: '" << args.input << "' holds " << file.pages
              << " pages or parts; only the first is enlarged\n";
  options.alpha_channel = header.alpha_channel;
  const OIIO::ParamValueList metadata = ddt::scaled_metadata(file.metadata, double(out_w) / header.width,
                                                             double(out_h) / header.height);
  ddt::ImageBandWriter writer(args.output, out_w, out_h, header.channels, header.format, header.alpha_channel,
                              &metadata, args.writing.encode);
  options.output_rows = [&writer](ddt::Image rows, int first_row) { writer.write(std::move(rows), first_row); };
  const int rows = args.tile_rows > 0 ? args.tile_rows
                                      : ddt::banded_rows(header.width, header.height, header.channels, out_w, out_h,
                                                         0.5 * double(ddt::available_memory()));
  log("read by bands of " + std::to_string(rows) + " rows: " + args.input + ", " + std::to_string(header.width) + "x" +
      std::to_string(header.height) + "x" + std::to_string(header.channels));
  const ddt::RowSource source{header.width, header.height, header.channels,
                              [&reader](int first, int end, float* p) { reader.read(first, end, p); }};
  const auto t0 = std::chrono::steady_clock::now();
  const ddt::UpscaleStats stats = ddt::upscale_banded(source, out_w, out_h, options, rows);
  log("bands: " + std::to_string(stats.tiles) + ", margin " + std::to_string(stats.tile_margin) + " rows, " +
      std::to_string(seconds_since(t0)) + " s");
  progress.begin("write");
  writer.finish();
  if (bar) bar->stop();
  if (!args.quiet && !args.verbose) std::cerr << args.output << ": " << out_w << "x" << out_h << "\n";
  return 0;
}

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
    progress.begin("read");
    auto t0 = std::chrono::steady_clock::now();
    ddt::UpscaleOptions options = upscale_options(args);
    if (args.verbose) options.log = log;
    options.progress = &progress;
    // The whole job is sized from the input's header, before a pixel is
    // decoded: output size, what the output's format can store, memory.
    // An image whose job does not fit (or --tile-rows N) is read, enlarged
    // and written by bands when nothing needs it whole.
    int out_w = 0, out_h = 0, compare_gap = 0;
    bool banded = false;
    ddt::ImageReadLimits limits;
    limits.max_pixels = args.max_input_pixels;
    limits.check = [&](const ddt::ImageHeader& header) {
      output_size(args, header.width, header.height, out_w, out_h);
      compare_gap = std::max(2, out_w / 256);
      const int written_w = args.compare.empty() ? out_w : 2 * out_w + compare_gap;
      ddt::check_image_writable(args.output, written_w, out_h, header.channels, header.format, header.alpha_channel,
                                args.writing.encode);
      if (!args.mesh_view.empty()) ddt::check_region(roi, header.width, header.height);
      const double whole_job = image_job_bytes(args, header, out_w, out_h);
      const bool can_band = !args.writing.no_stream && args.compare.empty() && args.mesh_view.empty() &&
                            options.optimizer == ddt::Optimizer::lawson && args.tile_rows >= 0 &&
                            ddt::optimizer_region_rows(header.width, header.height, options) > 0;
      banded = can_band && (args.tile_rows > 0 || whole_job > 0.9 * double(ddt::available_memory()));
      if (!banded) ddt::check_memory_fits("this job", whole_job);
    };
    std::unique_ptr<ddt::ImageRowReader> reader = std::make_unique<ddt::ImageRowReader>(args.input, limits);
    if (banded) return run_banded_job(args, *reader, out_w, out_h, options, progress, bar.get(), log);
    reader.reset();
    limits.check = [&](const ddt::ImageHeader& header) {
      ddt::check_memory_fits("this job", image_job_bytes(args, header, out_w, out_h));
    };
    ddt::ImageFile file = ddt::read_image(args.input, limits);
    log("read: " + args.input + ", " + std::to_string(file.image.width) + "x" + std::to_string(file.image.height) +
        "x" + std::to_string(file.image.channels) + ", " + std::to_string(seconds_since(t0)) + " s");
    if (file.pages > 1 && !args.quiet)
      std::cerr << "ddtscale: warning: '" << args.input << "' holds " << (file.pages > 2 ? std::to_string(file.pages) : "2 or more")
                << " pages or parts; only the first is enlarged\n";

    options.alpha_channel = file.alpha_channel;
    // Streamed (io/band_writer.hpp): bands of output rows are encoded as
    // they are rendered, on a thread of their own; --compare joins two
    // whole images, so it writes at the end.
    const OIIO::ParamValueList metadata = ddt::scaled_metadata(
        file.metadata, double(out_w) / file.image.width, double(out_h) / file.image.height);
    std::unique_ptr<ddt::ImageBandWriter> writer;
    if (!args.writing.no_stream && args.compare.empty()) {
      writer = std::make_unique<ddt::ImageBandWriter>(args.output, out_w, out_h, file.image.channels, file.format,
                                                      file.alpha_channel, &metadata, args.writing.encode);
      options.output_rows = [&writer](ddt::Image rows, int first_row) { writer->write(std::move(rows), first_row); };
    }
    ddt::UpscaleStats stats;
    ddt::Image out = ddt::upscale(file.image, out_w, out_h, options, &stats);
    const int written_w = writer ? out_w : out.width, written_h = writer ? out_h : out.height;
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
    if (writer) writer->finish();
    else ddt::write_image(args.output, out, file.format, file.alpha_channel, &metadata, args.writing.encode);
    log("write: " + args.output + ", " + std::to_string(seconds_since(t0)) + " s");
    if (bar) bar->stop();
    if (!args.quiet && !args.verbose)
      std::cerr << args.output << ": " << written_w << "x" << written_h << "\n";  // as written (--compare: both halves)
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
  // Bands of rows (a few MB each, allocated and freed by the hundred) are
  // served from freed heap memory instead of fresh pages, which cost a
  // page fault each on the machines measured (docs/performance.md).
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  if (argc >= 2 && std::strcmp(argv[1], "eval") == 0) return run_eval_command(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "grid") == 0) return run_grid_command(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "scene") == 0) return run_scene_command(argc - 1, argv + 1);
  if (is_volume_command(argc, argv)) return run_volume_command(argc, argv);
  if (is_sequence_command(argc, argv)) return run_sequence_command(argc, argv);
  return run_upscale(argc, argv);
}
