// ddtscale — enlarge images by data-dependent triangulation.
//   ddtscale in.png out.exr --scale 10
//   ddtscale eval --set DIR ...      (see `ddtscale eval --help`)

#include "batch.hpp"
#include "commands.hpp"
#include "output_options.hpp"
#include "whole_number.hpp"

#include "eval/classic_resize.hpp"
#include "eval/comparison.hpp"
#include "core/costs.hpp"
#include "io/band_writer.hpp"
#include "util/error.hpp"
#include "io/image_io.hpp"
#include "image/image_mesh.hpp"
#include "image/mesh_view.hpp"
#include "pipeline/output_size.hpp"
#include "util/progress.hpp"
#include "util/size_limits.hpp"
#include "pipeline/upscale.hpp"

#include <CLI/CLI.hpp>
#include <OpenImageIO/imageio.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <thread>

#include <unistd.h>

namespace {

struct Arguments {
  std::string input, output;
  double scale = 0;
  bool scale_given = false;
  bool width_given = false, height_given = false;  // on the command line
  int width = 0, height = 0;
  std::string cost = "sederberg";
  std::string cost_channel = "sum";
  bool no_optimize = false;
  double tolerance = 1e-9;
  long long max_pixels = ddt::default_max_pixels;
  long long max_input_pixels = ddt::default_max_input_pixels();
  bool verbose = false;
  bool quiet = false;
  int threads = 0;    // 0: all cores
  int tile_rows = 0;  // 0: automatic, < 0: never
  std::string optimizer = "lawson";
  ddt::AnnealOptions anneal;  // --seed and the --anneal-* schedule
  std::string render = "cubic";
  std::string slopes = "mc4";
  std::string model = "box";
  bool no_step_edges = false;
  std::string compare;    // classic method shown left of DDT, or empty
  std::string mesh_view;  // path of the mesh drawing, or empty
  std::string mesh_roi;   // x,y,w,h
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Output size from --scale / --width / --height; throws ddt::Error.
void output_size(const Arguments& args, int in_w, int in_h, int& out_w, int& out_h) {
  ddt::SizeRequest request;
  if (args.scale_given) request.scale = args.scale;
  if (args.width_given) request.width = args.width;
  if (args.height_given) request.height = args.height;
  request.max_pixels = args.max_pixels;
  ddt::output_size(request, in_w, in_h, out_w, out_h);
}

// The memory the job holds at least, whatever the tiling: the decoded input
// and the output as floats (with --compare also the classic half and the
// joined image), and the band being triangulated (about 200 bytes an input
// pixel, bounded by the tiling to half the physical memory).
double image_job_bytes(const Arguments& args, const ddt::ImageHeader& header, int out_w, int out_h, bool streamed) {
  const double in_pixels = double(header.width) * header.height;
  // Streamed under the point model, a few bands of the output are held.
  const bool bands = streamed && args.compare.empty() && args.model == "point";
  const double out_pixels = bands ? std::min(double(out_w) * out_h, 4.0 * 8192 * out_w) : double(out_w) * out_h;
  const double images = 4.0 * header.channels * (in_pixels + out_pixels * (args.compare.empty() ? 1 : 4));
  const bool tiled = args.optimizer == "lawson" && args.tile_rows >= 0;
  const double band = 200.0 * in_pixels;
  return images + (tiled ? std::min(band, 0.5 * double(ddt::physical_memory())) : band);
}

int run_upscale(int argc, char** argv) {
  Arguments args;
  CLI::App app{"ddtscale: enlarge an image by data-dependent triangulation (DDT).\n"
               "The pixels become a heightfield, triangulated (Delaunay, then edge flips that lower a cost)\n"
               "so that long thin triangles follow the edges; the surface on the mesh is rendered at the\n"
               "new size. Volumes: give .nrrd/.nhdr files (`ddtscale in.nrrd x.nrrd --help`). Subcommands:\n"
               "`ddtscale eval --help` (benchmark), `ddtscale grid --help` (scattered points),\n"
               "`ddtscale scene --help` (test scenes), `ddtscale volume-eval --help`, `ddtscale volume-field --help`.",
               "ddtscale"};
  app.add_option("input", args.input, "input image (PNG, JPEG, TIFF, EXR, ... anything OpenImageIO reads)")->required();
  app.add_option("output", args.output,
                 "output image; format from the extension (EXR keeps float, PNG/TIFF keep the input's bit depth)");
  // Many files at once (cli/batch.hpp): with --outdir every positional is an input.
  BatchOptions batch;
  std::vector<std::string> more_inputs;
  app.add_option("more", more_inputs)->group("");
  app.add_option("-s,--scale", args.scale, "magnification, any real > 0 (e.g. 10 or 2.5)");
  app.add_option("-W,--width", args.width, "output width in pixels (height follows the aspect unless given)")
      ->check(whole_number(1, std::numeric_limits<int>::max()));
  app.add_option("-H,--height", args.height, "output height in pixels (width follows the aspect unless given)")
      ->check(whole_number(1, std::numeric_limits<int>::max()));
  app.add_option("--cost", args.cost, "flip cost: " + ddt::cost_names_joined())->capture_default_str();
  app.add_option("--cost-channel", args.cost_channel,
                 "what drives the flips: sum (of per-channel costs) or luma (luminance only)")
      ->check(CLI::IsMember({"sum", "luma"}))
      ->capture_default_str();
  app.add_option("--render", args.render,
                 "surface drawn on the mesh: cubic (smooth Bézier patches, default) or linear (the paper's)")
      ->check(CLI::IsMember(ddt::render_names()))
      ->capture_default_str();
  app.add_option("--slopes", args.slopes, "cubic render: slope limiter of the vertex gradients: mc4, mc, central, minmod")
      ->check(CLI::IsMember({"mc4", "mc", "central", "minmod"}))
      ->capture_default_str();
  app.add_option("--model", args.model,
                 "how an input pixel was made: box (its area's average, default), gauss:SIGMA (the area blurred "
                 "by a Gaussian PSF of SIGMA input pixels), bicubic (MATLAB's antialiased imresize, the SR "
                 "benchmark's) or point (a sample at its centre: the plain interpolation). The output, mapped "
                 "back by the model, reproduces the input")
      ->check([](const std::string& text) {
        try {
          ddt::parse_acquisition_model(text);
          return std::string();
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
      })
      ->capture_default_str();
  app.add_flag("--no-step-edges", args.no_step_edges,
               "box model: keep the smooth reconstruction where one straight edge between two flat levels "
               "explains a pixel's 3x3 neighbourhood (by default it is drawn as that edge, sharp to the output "
               "pixel)");
  app.add_flag("--no-optimize", args.no_optimize, "skip the flips: render the initial Delaunay mesh");
  app.add_option("--tolerance", args.tolerance, "a flip must lower the local cost by more than this fraction")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--max-pixels", args.max_pixels, "refuse outputs with more pixels than this")
      ->check(whole_number(1))
      ->capture_default_str();
  app.add_option("--max-input-pixels", args.max_input_pixels,
                 "refuse inputs with more pixels than this, from the file's header before decoding (default: "
                 "the physical memory / 32)")
      ->check(whole_number(1))
      ->capture_default_str();
  app.add_option("--compare", args.compare,
                 "write one image: this classic method (OpenImageIO filter) on the left, DDT on the right")
      ->check(CLI::IsMember(ddt::classic_methods()));
  app.add_option("--mesh", args.mesh_view,
                 "also draw the optimized triangulation over the input (.svg, or .png and other raster formats)");
  app.add_option("--mesh-roi", args.mesh_roi,
                 "x,y,w,h: the input region the mesh view shows (default: all of an image up to 256x256, "
                 "else its central 128x128)");
  bool list_costs = false;
  app.add_flag("--list-costs", list_costs, "print the cost names, one a line, and exit");
  add_optimizer_options(app, args.optimizer, args.anneal);
  app.add_flag("-v,--verbose", args.verbose, "report iterations, flips, cost and the time of each stage");
  app.add_flag("-q,--quiet", args.quiet, "print nothing but errors (and no progress bar)");
  app.add_option("--threads", args.threads, "threads to use (default: all cores; more than the cores are not used)")
      ->check(whole_number(0, 4096));
  app.add_option("--tile-rows", args.tile_rows,
                 "process the image in bands of this many input rows (same output; default: only when it would "
                 "not fit in half the memory; -1: never)")
      ->check(whole_number(-1, std::numeric_limits<int>::max()));
  add_batch_options(app, batch);
  OutputOptions output;
  add_output_options(app, output);
  app.footer(
      "\nCosts (the paper's weighted content, sum over triangles of area * weight):\n"
      "  sederberg       weight = mean over the triangle's edges of |g1||g2| - g1.g2 (default)\n"
      "  variance        weight = variance of the three vertex values\n"
      "  sederberg-edge  classic 2D DDT: sum over interior edges of |g1||g2| - g1.g2\n"
      "  abn, jnd, dlp, dp   weight = mean over the triangle's edges of a classic cost of Dyn, Levin and\n"
      "                  Rippa (1990): angle between normals, jump in normal derivatives, deviation from\n"
      "                  linear polynomials, distance from planes\n"
      "  abn-edge, jnd-edge, dlp-edge, dp-edge   the same costs as plain sums over interior edges\n"
      "Optimizers: lawson flips while a flip lowers the cost; anneal (simulated annealing) also takes\n"
      "flips that raise it, with probability exp(-increase / T), T cooling geometrically from T0 over\n"
      "--anneal-steps steps of --anneal-moves proposals per edge, then finishes with lawson; lookahead\n"
      "runs lawson, then also keeps a cost-raising flip when a flip of a neighbouring edge then lowers\n"
      "the total by more, alternating with lawson until neither finds a move.\n"
      "Render: cubic (default) draws a cubic Bézier patch on each triangle from the vertex values and\n"
      "slope-limited gradients (--slopes), smooth like bicubic inside regions, no ringing at edges;\n"
      "linear draws the paper's piecewise-linear surface. Both reproduce the input samples exactly.\n"
      "Alpha is interpolated on the same mesh and never drives flips.\n"
      "Output pixel (X, Y) samples the input at ((X + 0.5) / sx, (Y + 0.5) / sy); outside the samples'\n"
      "hull it takes the value of the nearest hull point.\n"
      "Examples:\n"
      "  ddtscale in.png out.exr --scale 10\n"
      "  ddtscale in.png side.png --scale 8 --compare bicubic --mesh mesh.svg --mesh-roi 40,40,64,64\n"
      "  ddtscale a.png b.jpg scans/ 'more/*.tif' --outdir out/ --suffix _x4 --scale 4");
  // --list-costs needs no files: answer it before the positional checks.
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--list-costs") == 0) {
      for (const auto& c : ddt::cost_functions()) std::cout << c.name << "\n";
      return 0;
    }
  try {
    app.parse(argc, argv);
    args.scale_given = app.count("--scale") > 0;
    args.width_given = app.count("--width") > 0;
    args.height_given = app.count("--height") > 0;
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    std::cerr << "ddtscale: " << e.what() << " (see ddtscale --help)\n";
    return 2;
  }
  if (!batch.outdir.empty()) {
    std::vector<std::string> inputs = {args.input};
    if (!args.output.empty()) inputs.push_back(args.output);
    inputs.insert(inputs.end(), more_inputs.begin(), more_inputs.end());
    return run_batch(app, inputs, batch, args.quiet);
  }
  if (args.output.empty() || !more_inputs.empty()) {
    std::cerr << "ddtscale: give an input and an output image (many inputs: --outdir DIR) (see ddtscale --help)\n";
    return 2;
  }

  try {
    ddt::find_cost(args.cost);  // fail fast on a typo
    if (!(args.tolerance >= 0.0 && args.tolerance <= 1.0))  // CLI::Range lets NaN through
      throw ddt::Error("--tolerance must be a number in [0, 1]");
    ddt::check_output_path(args.output, args.input);
    ddt::check_encode_options(args.output, output.encode);
    ddt::PixelRegion roi;
    if (!args.mesh_roi.empty()) roi = ddt::parse_region(args.mesh_roi);
    if (!args.mesh_view.empty()) {
      const bool svg = args.mesh_view.size() > 4 && args.mesh_view.substr(args.mesh_view.size() - 4) == ".svg";
      ddt::check_output_path(args.mesh_view, args.input, !svg);
      if (args.mesh_view == args.output) throw ddt::Error("--mesh must name a file other than the output");
    }
    // Both cores unless --threads says otherwise (TBB for our stages, OIIO's pool for reading and writing).
    std::unique_ptr<tbb::global_control> thread_limit;
    // More threads than cores only slow the work down (each its own buffers).
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    if (args.threads > cores) args.threads = cores;
    if (args.threads > 0) {
      thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, args.threads);
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
    // The whole job is sized from the input's header, before a pixel is
    // decoded: output size, what the output's format can store, memory.
    int out_w = 0, out_h = 0, compare_gap = 0;
    ddt::ImageReadLimits limits;
    limits.max_pixels = args.max_input_pixels;
    limits.check = [&](const ddt::ImageHeader& header) {
      output_size(args, header.width, header.height, out_w, out_h);
      compare_gap = std::max(2, out_w / 256);
      const int written_w = args.compare.empty() ? out_w : 2 * out_w + compare_gap;
      ddt::check_image_writable(args.output, written_w, out_h, header.channels, header.format, header.alpha_channel,
                                output.encode);
      if (!args.mesh_view.empty()) ddt::check_region(roi, header.width, header.height);
      ddt::check_memory_fits("this job", image_job_bytes(args, header, out_w, out_h, !output.no_stream));
    };
    ddt::ImageFile file = ddt::read_image(args.input, limits);
    log("read: " + args.input + ", " + std::to_string(file.image.width) + "x" + std::to_string(file.image.height) +
        "x" + std::to_string(file.image.channels) + ", " + std::to_string(seconds_since(t0)) + " s");
    if (file.pages > 1 && !args.quiet)
      std::cerr << "ddtscale: warning: '" << args.input << "' holds " << (file.pages > 2 ? std::to_string(file.pages) : "2 or more")
                << " pages or parts; only the first is enlarged\n";

    ddt::UpscaleOptions options;
    options.cost = args.cost;
    options.luma_cost = args.cost_channel == "luma";
    options.alpha_channel = file.alpha_channel;
    options.optimize = !args.no_optimize;
    options.render = args.render;
    options.slopes = args.slopes;
    options.model = ddt::parse_acquisition_model(args.model);
    options.step_edges = !args.no_step_edges;
    options.relative_tolerance = args.tolerance;
    options.optimizer = args.optimizer;
    options.anneal = args.anneal;
    if (args.verbose) options.log = log;
    options.progress = &progress;
    options.tile_rows = args.tile_rows;
    // Streamed (io/band_writer.hpp): bands of output rows are encoded as
    // they are rendered, on a thread of their own; --compare joins two
    // whole images, so it writes at the end.
    const OIIO::ParamValueList metadata = ddt::scaled_metadata(
        file.metadata, double(out_w) / file.image.width, double(out_h) / file.image.height);
    std::unique_ptr<ddt::ImageBandWriter> writer;
    if (!output.no_stream && args.compare.empty()) {
      writer = std::make_unique<ddt::ImageBandWriter>(args.output, out_w, out_h, file.image.channels, file.format,
                                                      file.alpha_channel, &metadata, output.encode);
      options.output_rows = [&writer](ddt::Image rows, int first_row) { writer->write(std::move(rows), first_row); };
    }
    ddt::UpscaleStats stats;
    ddt::Image out = ddt::upscale(file.image, out_w, out_h, options, &stats);
    const int written_w = writer ? out_w : out.width, written_h = writer ? out_h : out.height;
    if (stats.consistency_skipped && !args.quiet)
      std::cerr << "ddtscale: warning: the image was processed in " << stats.tiles
                << " tiles, where --model " << args.model << " is not applied (plain interpolation, --model point)\n";
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
    else ddt::write_image(args.output, out, file.format, file.alpha_channel, &metadata, output.encode);
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

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "eval") == 0) return run_eval_command(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "grid") == 0) return run_grid_command(argc - 1, argv + 1);
  if (argc >= 2 && std::strcmp(argv[1], "scene") == 0) return run_scene_command(argc - 1, argv + 1);
  if (is_volume_command(argc, argv)) return run_volume_command(argc, argv);
  return run_upscale(argc, argv);
}
