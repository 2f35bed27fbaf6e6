#include "batch.hpp"
#include "whole_number.hpp"

#include <CLI/CLI.hpp>

#include <set>
#include <string>
#include <vector>

std::vector<std::string> forwarded_options(const CLI::App& app) {
  static const std::set<std::string> batch_only = {"--outdir", "--suffix", "--format", "--overwrite", "--jobs",
                                                   "--help", "--quiet"};
  std::vector<std::string> args;
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_positional() || opt->count() == 0) continue;
    const std::string name = opt->get_name();
    if (batch_only.count(name)) continue;
    // --name=value: flags take their value that way too (--verbose=true).
    for (const auto& value : opt->results()) args.push_back(name + "=" + value);
  }
  return args;
}

void add_batch_options(CLI::App& app, BatchOptions& batch) {
  app.add_option("--outdir", batch.outdir,
                 "many inputs: every positional argument is an input (files, directories, globs), each written "
                 "to this directory as STEM SUFFIX.EXT");
  app.add_option("--suffix", batch.suffix, "with --outdir: added to each output's name (e.g. _x4)");
  app.add_option("--format", batch.format, "with --outdir: the outputs' extension (e.g. exr; default: the input's)");
  app.add_flag("--overwrite", batch.overwrite, "with --outdir: replace existing outputs (default: skip them)");
  app.add_option("--jobs", batch.jobs, "with --outdir: files processed at once (default: one per core)")
      ->check(whole_number(0, 4096));
}
