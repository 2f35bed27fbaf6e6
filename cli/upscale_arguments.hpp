#pragma once
// The image command's command line (`ddtscale in.png out.png --scale 4 ...`)
// as a typed job description, parsed and validated without touching a file,
// so the parser can be fuzzed in-process (fuzz/fuzz_cli.cpp) and the run
// (cli/main.cpp) starts from checked values.
//
//   parse_upscale_command_line  argv -> what to do (run, batch, help, ...);
//                               CLI11's checks (types, ranges, names)
//   validate_arguments          the checks CLI11 cannot make (NaN
//                               tolerance, unknown cost, malformed --mesh-roi,
//                               --mesh naming the output): ddt::Error
//   size_request                --scale / --width / --height / --max-pixels
//                               as the library's SizeRequest
//   upscale_options             the method's flags as UpscaleOptions
// None of them reads or writes a file, prints, or starts a thread.

#include "batch.hpp"
#include "output_options.hpp"

#include "image/annealing.hpp"
#include "pipeline/output_size.hpp"
#include "pipeline/upscale.hpp"
#include "util/size_limits.hpp"

#include <string>
#include <vector>

namespace ddt {
struct ImageHeader;
}

// The single-file image job, as given on the command line (defaults are the
// library's, UpscaleOptions', named for the command line).
inline const ddt::UpscaleOptions upscale_defaults;

struct UpscaleArguments {
  std::string input, output;
  double scale = 0;
  bool scale_given = false;
  bool width_given = false, height_given = false;  // on the command line
  int width = 0, height = 0;
  std::string cost = upscale_defaults.cost;
  std::string cost_channel = upscale_defaults.luma_cost ? "luma" : "sum";
  bool no_optimize = !upscale_defaults.optimize;
  double tolerance = upscale_defaults.relative_tolerance;
  long long max_pixels = ddt::default_max_pixels;
  long long max_input_pixels = ddt::default_max_input_pixels();
  bool verbose = false;
  bool quiet = false;
  int threads = 0;    // 0: all cores
  int tile_rows = upscale_defaults.tile_rows;  // 0: automatic, < 0: never
  int mesh_band_rows = upscale_defaults.mesh_band_rows;  // 0: automatic, < 0: one mesh
  std::string max_memory;  // --max-memory SIZE (e.g. 2G); empty: automatic
  std::string optimizer = ddt::to_string(upscale_defaults.optimizer);
  ddt::AnnealOptions anneal = upscale_defaults.anneal;  // --seed and the --anneal-* schedule
  std::string render = ddt::to_string(upscale_defaults.render);
  std::string slopes = ddt::to_string(upscale_defaults.slopes);
  std::string model = ddt::to_string(upscale_defaults.model);
  bool no_step_edges = !upscale_defaults.step_edges;
  std::string compare;    // classic method shown left of DDT, or empty
  std::string mesh_view;  // path of the mesh drawing, or empty
  std::string mesh_roi;   // x,y,w,h
  OutputOptions writing;  // --compression, --quality, --half, --tile-size, --no-stream
};

struct UpscaleCommandLine {
  enum class Action {
    run,          // one job: `args`
    batch,        // many files: `batch`, `batch_inputs`, `forwarded`
    help,         // print `text` on stdout, exit 0
    list_costs,   // print the cost names, exit 0
    version,      // print the version and the libraries', exit 0
    usage_error,  // print "ddtscale: " + `text` on stderr, exit 2
  };
  Action action = Action::run;
  UpscaleArguments args;
  std::string text;
  BatchOptions batch;
  std::vector<std::string> batch_inputs;  // every positional, in order
  std::vector<std::string> forwarded;     // the options each file's run gets
};

// argv[0] is the program; argc >= 1. Never throws for any argv (a CLI11
// error is a usage_error with CLI11's message and the --help hint).
UpscaleCommandLine parse_upscale_command_line(int argc, const char* const* argv);

// Throws ddt::Error with the one-line message of the first check that fails.
void validate_arguments(const UpscaleArguments& args);

// --scale / --width / --height / --max-pixels as given (pipeline/output_size.hpp).
ddt::SizeRequest size_request(const UpscaleArguments& args);

// The library's options for the job (without log and progress, which the run sets).
ddt::UpscaleOptions upscale_options(const UpscaleArguments& args);
