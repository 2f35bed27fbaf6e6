#pragma once
#include <string>

namespace CLI {
class App;
}
namespace ddt {
struct AnnealOptions;
}

// Subcommands of the ddtscale binary, dispatched from main(). Each takes the
// arguments from the subcommand's name on (argv[0] is e.g. "eval"), prints
// errors as one line on stderr, and returns the process exit status.

// `ddtscale eval`: the super-resolution evaluation protocol (evaluation.hpp)
// over an image directory or the synthetic scenes. 0 on success (and for
// --help), 1 when the work fails (missing set, corrupt image), 2 on bad
// arguments.
int run_eval_command(int argc, char** argv);

// `ddtscale grid`: scattered points (x, y, values) to a regular grid image
// by DDT (gridding.hpp). 0 on success (and for --help), 1 on a runtime
// error, 2 on bad arguments.
int run_grid_command(int argc, char** argv);

// `ddtscale scene`: render an analytic test scene (synthetic_scenes.hpp) to
// an image file. 0 on success, 1 on a runtime error, 2 on bad arguments.
int run_scene_command(int argc, char** argv);

// Volumes by data-dependent tetrahedrization (volume_upscale.hpp):
//   ddtscale in.nrrd out.nrrd --scale 4   (chosen when any argument names a
//                                          .nrrd or .nhdr file)
//   ddtscale volume-eval ...              the paper's 3D experiments
//   ddtscale volume-field ...             write an analytic test volume
// is_volume_command tells main() whether to dispatch here; run_volume_command
// takes the whole command line (argv[0] the program). 0 on success (and for
// --help), 1 on a runtime error, 2 on bad arguments.
bool is_volume_command(int argc, char** argv);
int run_volume_command(int argc, char** argv);

// Image sequences by data-dependent tetrahedrization of (x, y, t)
// (sequence_upscale.hpp):
//   ddtscale in_%04d.png out_%04d.png --time-scale 4 [--scale 2]
// chosen when an argument is a printf-style frame pattern
// (frame_sequence.hpp). 0 on success (and for --help), 1 on a runtime
// error, 2 on bad arguments.
bool is_sequence_command(int argc, char** argv);
int run_sequence_command(int argc, char** argv);

// --optimizer, --seed and the --anneal-* schedule, shared by the image and
// the grid commands.
void add_optimizer_options(CLI::App& app, std::string& optimizer, ddt::AnnealOptions& anneal);
