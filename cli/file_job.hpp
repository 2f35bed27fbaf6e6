#pragma once
// The image command's jobs as both programs run them: ddtscale-full
// (cli/main.cpp) and the `ddtscale` front (cli/front_main.cpp), which runs
// PNG to PNG without OpenImageIO (io/image_formats.hpp).

#include "upscale_arguments.hpp"

#include "util/progress.hpp"

#include <cstdio>
#include <functional>
#include <memory>
#include <string>

// What a job shows while it runs: a progress bar on a terminal for runs
// over a second (unless --quiet), and --verbose's lines (above the bar).
class JobConsole {
 public:
  JobConsole(bool quiet, bool verbose);
  ~JobConsole();
  JobConsole(const JobConsole&) = delete;
  JobConsole& operator=(const JobConsole&) = delete;

  ddt::Progress& progress() { return progress_; }
  // Prints a --verbose line (nothing without --verbose).
  void log(const std::string& line);
  void stop();  // the bar, before the last line

 private:
  bool verbose_;
  ddt::Progress progress_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> bar_out_;
  std::unique_ptr<ddt::ProgressBar> bar_;
};

// Runs `job`, printing its failure as one line on stderr: returns its
// status, or 1. ddt::NeedsOpenImageIO passes through (the front's cue).
int report_failure(const std::function<int()>& job);

// `ddtscale IN OUT ...` without --compare and --mesh (validated
// arguments): the file enlarged into the output (pipeline/file_upscale.hpp).
// Returns the exit status.
int run_file_job(UpscaleArguments args);
