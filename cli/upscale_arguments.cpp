#include "upscale_arguments.hpp"

#include "io/encode_options.hpp"

#include "commands.hpp"
#include "whole_number.hpp"

#include "consistency/acquisition_model.hpp"
#include "core/costs.hpp"
#include "eval/classic_resize.hpp"
#include "image/mesh_view.hpp"
#include "io/image_io.hpp"
#include "util/error.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstring>
#include <limits>

UpscaleCommandLine parse_upscale_command_line(int argc, const char* const* argv) {
  UpscaleCommandLine line;
  UpscaleArguments& args = line.args;
  CLI::App app{"ddtscale: enlarge an image by data-dependent triangulation (DDT).\n"
               "The pixels become a heightfield, triangulated (Delaunay, then edge flips that lower a cost)\n"
               "so that long thin triangles follow the edges; the surface on the mesh is rendered at the\n"
               "new size. Volumes: give .nrrd/.nhdr files (`ddtscale in.nrrd x.nrrd --help`). Image sequences\n"
               "and videos (frame-rate upsampling): give frame patterns or video files\n"
               "(`ddtscale in_%04d.png out_%04d.png --help`). Subcommands: `ddtscale eval --help` (benchmark),\n"
               "`ddtscale grid --help` (scattered points), `ddtscale scene --help` (test scenes),\n"
               "`ddtscale volume-eval --help`, `ddtscale volume-field --help`, `ddtscale sequence-eval --help`.",
               "ddtscale"};
  app.add_option("input", args.input, "input image (PNG, JPEG, TIFF, EXR, ... anything OpenImageIO reads)")->required();
  app.add_option("output", args.output,
                 "output image; format from the extension (EXR keeps float, PNG/TIFF keep the input's bit depth)");
  // Many files at once (cli/batch.hpp): with --outdir every positional is an input.
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
      ->check(CLI::IsMember(ddt::slope_limiter_names()))
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
  bool list_costs = false, version = false;
  app.add_flag("--list-costs", list_costs, "print the cost names, one a line, and exit");
  app.add_flag("-V,--version", version, "print the version of ddtscale and of the libraries it runs on, and exit");
  add_optimizer_options(app, args.optimizer, args.anneal);
  app.add_flag("-v,--verbose", args.verbose, "report iterations, flips, cost and the time of each stage");
  app.add_flag("-q,--quiet", args.quiet, "print nothing but errors (and no progress bar)");
  app.add_option("--threads", args.threads, "threads to use (default: all cores; more than the cores are not used)")
      ->check(whole_number(0, 4096));
  app.add_option("--tile-rows", args.tile_rows,
                 "process the image in bands of this many input rows, read, enlarged and written band by band "
                 "where the format allows (same output, less memory; default: only when the job would not fit "
                 "in memory; -1: never)")
      ->check(whole_number(-1, std::numeric_limits<int>::max()));
  app.add_option("--mesh-band-rows", args.mesh_band_rows,
                 "box model at whole scales, streamed: build the mesh in bands of this many input rows, each "
                 "made as the reconstruction reaches it and freed before the next, the input file read by rows "
                 "(same output, less memory, the bands' margins redone; default: on images tall enough to gain; "
                 "-1: one mesh)")
      ->check(whole_number(-1, std::numeric_limits<int>::max()));
  app.add_option("--max-memory", args.max_memory,
                 "memory target of the job (e.g. 2G, 512M): a larger job is read, enlarged and written by "
                 "bands of rows sized by a memory model to fit (the same output, slower: the bands' margins are "
                 "redone; a target, not a hard cap), or refused with the size to give (default: bands only when "
                 "the job would not fit in the memory available)")
      ->check(CLI::Validator(
          [](std::string& text) {
            try {
              ddt::parse_memory_size(text);
              return std::string();
            } catch (const std::exception& e) {
              return std::string(e.what());
            }
          },
          "SIZE"));
  add_batch_options(app, line.batch);
  add_output_options(app, line.args.writing);
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
      "linear draws the paper's piecewise-linear surface. Alpha is interpolated on the same mesh and\n"
      "never drives flips. Output pixel (X, Y) samples the surface at ((X + 0.5) / sx, (Y + 0.5) / sy);\n"
      "outside the samples' hull it takes the value of the nearest hull point. Then the output is\n"
      "corrected until --model maps it back onto the input (the default, box: each input pixel the mean\n"
      "of the output pixels over its area); --model point keeps the surface through the input samples.\n"
      "Examples:\n"
      "  ddtscale in.png out.exr --scale 10\n"
      "  ddtscale in.png side.png --scale 8 --compare bicubic --mesh mesh.svg --mesh-roi 40,40,64,64\n"
      "  ddtscale a.png b.jpg scans/ 'more/*.tif' --outdir out/ --suffix _x4 --scale 4");
  // --list-costs and --version need no files: answer them before the positional checks.
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--list-costs") == 0) {
      line.action = UpscaleCommandLine::Action::list_costs;
      return line;
    }
    // -V alone: elsewhere it may be an option's value (e.g. --suffix -V).
    if (std::strcmp(argv[i], "--version") == 0 || (argc == 2 && std::strcmp(argv[i], "-V") == 0)) {
      line.action = UpscaleCommandLine::Action::version;
      return line;
    }
  }
  try {
    app.parse(argc, argv);
    args.scale_given = app.count("--scale") > 0;
    args.width_given = app.count("--width") > 0;
    args.height_given = app.count("--height") > 0;
    if (version) {
      line.action = UpscaleCommandLine::Action::version;
      return line;
    }
  } catch (const CLI::CallForHelp&) {
    line.action = UpscaleCommandLine::Action::help;
    line.text = app.help();
    return line;
  } catch (const CLI::ParseError& e) {
    line.action = UpscaleCommandLine::Action::usage_error;
    line.text = std::string(e.what()) + " (see ddtscale --help)";
    return line;
  }
  if (!line.batch.outdir.empty()) {
    line.action = UpscaleCommandLine::Action::batch;
    line.batch_inputs = {args.input};
    if (!args.output.empty()) line.batch_inputs.push_back(args.output);
    line.batch_inputs.insert(line.batch_inputs.end(), more_inputs.begin(), more_inputs.end());
    line.forwarded = forwarded_options(app);
    return line;
  }
  if (args.output.empty() || !more_inputs.empty()) {
    line.action = UpscaleCommandLine::Action::usage_error;
    line.text = "give an input and an output image (many inputs: --outdir DIR) (see ddtscale --help)";
  }
  return line;
}

void validate_arguments(const UpscaleArguments& args) {
  ddt::find_cost(args.cost);  // fail fast on a typo
  if (!args.output.empty()) ddt::check_encode_options(args.output, args.writing.encode);
  if (!(args.tolerance >= 0.0 && args.tolerance <= 1.0))  // CLI::Range lets NaN through
    throw ddt::Error("--tolerance must be a number in [0, 1]");
  if (!args.mesh_roi.empty()) ddt::parse_region(args.mesh_roi);
  if (!args.mesh_view.empty() && args.mesh_view == args.output)
    throw ddt::Error("--mesh must name a file other than the output");
}

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
  options.mesh_band_rows = args.mesh_band_rows;
  options.max_memory = args.max_memory.empty() ? 0 : ddt::parse_memory_size(args.max_memory);
  return options;
}

ddt::SizeRequest size_request(const UpscaleArguments& args) {
  ddt::SizeRequest request;
  if (args.scale_given) request.scale = args.scale;
  if (args.width_given) request.width = args.width;
  if (args.height_given) request.height = args.height;
  request.max_pixels = args.max_pixels;
  return request;
}
