#pragma once
// ddt::Progress — how far a long computation has got, for a display to
// poll; ddt::ProgressBar — that display on a terminal (stderr).
//
// Progress is thread-safe: the computation begins stages (a name and the
// units of work it expects, 0 when unknown), and any of its threads adds
// or sets the units done; a display thread takes snapshots. Each call is
// an atomic operation (begin takes a lock): report in batches, not per
// pixel.
//
// Cancelling: cancel() (from any thread, e.g. one that saw Ctrl-C) makes
// every later begin, add and set throw ddt::Cancelled in the computation's
// threads, so the computation stops at its next report, unwinding as for
// any error (TBB carries the exception out of a parallel loop). How soon
// depends on how often the computation reports (the image pipeline: at
// each stage, the optimizer's tests, the render's chunks).
//
// ProgressBar polls a Progress from a background thread and redraws one
// line ("optimize [=========>         ] 45%  3.1 s") every `period`, but only
// once `delay` has passed, so short runs print nothing. stop() (or the
// destructor) erases the line. It is meant for terminals: callers check
// is_terminal(stderr) and their --quiet flag before creating one.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace ddt {

// Thrown by Progress's reports once it is cancelled; not an Error (the
// computation did not fail, its caller stopped it).
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

class Progress {
 public:
  struct Snapshot {
    std::string stage;        // empty before the first stage
    std::int64_t done = 0;
    std::int64_t total = 0;   // 0: unknown
    // done / total in [0, 1]; 0 when the total is unknown.
    double fraction() const;
  };

  // Starts stage `stage` with `total` units of work expected (0: unknown).
  // Each throws Cancelled once cancel() was called.
  void begin(const std::string& stage, std::int64_t total = 0);
  void add(std::int64_t units) {
    stop_if_cancelled();
    done_.fetch_add(units, std::memory_order_relaxed);
  }
  void set(std::int64_t done) {
    stop_if_cancelled();
    done_.store(done, std::memory_order_relaxed);
  }
  Snapshot snapshot() const;

  void cancel() { cancelled_.store(true, std::memory_order_relaxed); }
  bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

 private:
  mutable std::mutex mutex_;
  std::string stage_;
  std::atomic<std::int64_t> done_{0};
  std::atomic<std::int64_t> total_{0};
  std::atomic<bool> cancelled_{false};
  void stop_if_cancelled() const {
    if (cancelled()) throw Cancelled();
  }
};

class ProgressBar {
 public:
  struct Options {
    std::chrono::milliseconds delay{1000};  // nothing is drawn before this
    std::chrono::milliseconds period{100};  // redraw interval
    int width = 30;                         // characters between the brackets
    std::string prefix = "ddtscale: ";
  };

  ProgressBar(const Progress& progress, std::FILE* out, Options options);
  ProgressBar(const Progress& progress, std::FILE* out) : ProgressBar(progress, out, Options{}) {}
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  ~ProgressBar();

  // Stops the thread and erases the bar's line; idempotent.
  void stop();
  // Writes `line` (and a newline) on the output, the bar erased first and
  // redrawn at the next period: for log lines printed while the bar runs.
  void print(const std::string& line);
  // True when `f` is a terminal.
  static bool is_terminal(std::FILE* f);
  // The text of the bar for a snapshot after `seconds` (no control codes).
  static std::string format(const Progress::Snapshot& s, double seconds, int width);

 private:
  void run();
  void draw_locked();
  void erase_locked();

  const Progress& progress_;
  std::FILE* out_;
  Options options_;
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  bool drawn_ = false;  // a bar line is on the output
  std::thread thread_;
};

}  // namespace ddt
