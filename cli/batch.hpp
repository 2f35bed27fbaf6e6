#pragma once
// Many files at once:
//   ddtscale a.png b.jpg dir/ 'scans/*.tif' --outdir out/ --scale 4
// Inputs are files, directories (their image files, not recursed) and
// globs; each output is OUTDIR/STEM SUFFIX.EXT (EXT the input's, or
// --format). Every file runs as its own `ddtscale INPUT OUTPUT OPTIONS
// --quiet` process (the single-file command, unchanged), --jobs at a time,
// so one file's failure, memory or crash cannot stop the others.
// Prints one line per failed file, a progress bar over files on a terminal,
// and a summary (done, skipped, failed, time). Exit status: 0 when no file
// failed, 1 otherwise, 2 on bad arguments.

#include <string>
#include <vector>

namespace CLI {
class App;
}

struct BatchOptions {
  std::string outdir;   // empty: the single-file command
  std::string suffix;   // added to each output's stem
  std::string format;   // output extension without the dot; empty: the input's
  bool overwrite = false;
  int jobs = 0;         // files at once; 0: one per core
};

// Adds --outdir, --suffix, --format, --overwrite and --jobs to `app`.
void add_batch_options(CLI::App& app, BatchOptions& batch);

// The options given on the parsed command line `app`, as arguments for the
// single-file command (--name=value; batch options, positionals, --help and
// --quiet left out).
std::vector<std::string> forwarded_options(const CLI::App& app);

// Runs the single-file command with the options `forwarded` over the files
// `inputs` (the positionals); `quiet`: no progress or summary.
int run_batch(const std::vector<std::string>& forwarded, const std::vector<std::string>& inputs,
              const BatchOptions& batch, bool quiet);
