#pragma once
// Subcommands of the ddtscale binary, dispatched from main(). Each takes the
// arguments from the subcommand's name on (argv[0] is e.g. "eval"), prints
// errors as one line on stderr, and returns the process exit status.

// `ddtscale eval`: the super-resolution evaluation protocol (evaluation.hpp)
// over an image directory or the synthetic scenes. 0 on success (and for
// --help), 2 on any error.
int run_eval_command(int argc, char** argv);
