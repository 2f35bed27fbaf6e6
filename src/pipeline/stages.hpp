#pragma once
// ddt::StageRunner — the glue every pipeline (images, the mesh view,
// scattered points, volumes) shares around its stages (triangulate,
// optimize, render, ...): each stage timed, its verbose lines sent on, the
// progress told which stage runs, and the optimizer's summary and the
// stage seconds gathered into the statistics parts of ddtscale/stats.hpp (StageSeconds, OptimizerSummary),
// of which the pipelines' own stats are made.
//
// The lines themselves stay with each pipeline (they name what it counts);
// the runner owns only what they had in common.

#include "ddtscale/stats.hpp"
#include "util/progress.hpp"

#include <functional>
#include <string>
#include <utility>

namespace ddt {

// The Lawson settings every pipeline passes on from its options (which
// all name them relative_tolerance and max_iterations): written once.
template <class Lawson, class Options>
Lawson lawson_options(const Options& options) {
  Lawson lawson;
  lawson.relative_tolerance = options.relative_tolerance;
  lawson.max_iterations = options.max_iterations;
  return lawson;
}

class StageRunner {
 public:
  using Log = std::function<void(const std::string&)>;

  // log: verbose lines (may be empty); progress: may be null.
  explicit StageRunner(Log log, Progress* progress = nullptr) : log_(std::move(log)), progress_(progress) {}

  bool logging() const { return static_cast<bool>(log_); }
  void log(const std::string& line) const {
    if (log_) log_(line);
  }
  // The log as a function, empty when there is none (for the optimizers'
  // own lines).
  Log logger() const { return log_; }
  Progress* progress() const { return progress_; }

  // Tells the progress that stage `name` starts, with `total` units of
  // work expected (0: unknown).
  void begin(const std::string& name, long long total = 0) const {
    if (progress_) progress_->begin(name, total);
  }

 private:
  Log log_;
  Progress* progress_;
};

}  // namespace ddt
