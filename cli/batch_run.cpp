#include "batch.hpp"

#include "util/text.hpp"
#include "util/progress.hpp"

#include <CLI/CLI.hpp>
#include <OpenImageIO/imageio.h>

#include <fcntl.h>
#include <glob.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <thread>

extern char** environ;

namespace fs = std::filesystem;
using ddt::lower;

namespace {

struct Job {
  std::string input, output;
  std::string error;  // set when the file fails before it runs
};

// The extensions OpenImageIO reads, lower case without the dot.
const std::set<std::string>& image_extensions() {
  static const std::set<std::string> extensions = [] {
    std::set<std::string> e;
    for (const auto& [format, list] : OIIO::get_extension_map())
      for (const auto& ext : list) e.insert(lower(ext));
    return e;
  }();
  return extensions;
}

bool is_image_name(const fs::path& p) {
  const std::string ext = lower(p.extension().string());
  return ext.size() > 1 && image_extensions().count(ext.substr(1)) > 0;
}

// Files, directories (their image files, sorted) and globs, in the given order.
std::vector<std::string> expand_inputs(const std::vector<std::string>& inputs, std::vector<Job>& failed) {
  std::vector<std::string> files;
  for (const auto& input : inputs) {
    std::error_code ec;
    if (fs::is_directory(input, ec)) {
      std::vector<std::string> found;
      for (const auto& entry : fs::directory_iterator(input, ec))
        if (entry.is_regular_file(ec) && is_image_name(entry.path())) found.push_back(entry.path().string());
      std::sort(found.begin(), found.end());
      if (found.empty()) failed.push_back({input, "", "no image files in the directory"});
      files.insert(files.end(), found.begin(), found.end());
    } else if (input.find_first_of("*?[") != std::string::npos && !fs::exists(input, ec)) {
      glob_t matches{};
      if (::glob(input.c_str(), 0, nullptr, &matches) == 0) {
        for (std::size_t i = 0; i < matches.gl_pathc; ++i)
          if (fs::is_regular_file(matches.gl_pathv[i], ec)) files.push_back(matches.gl_pathv[i]);
      } else {
        failed.push_back({input, "", "no file matches"});
      }
      ::globfree(&matches);
    } else {
      files.push_back(input);  // a missing file fails in its own run, with the reader's message
    }
  }
  return files;
}

// The last non-empty line of `path`, without the program's "ddtscale: " prefix.
std::string last_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  const std::string prefix = "ddtscale: ";
  if (last.rfind(prefix, 0) == 0) last = last.substr(prefix.size());
  return last;
}

}  // namespace

int run_batch(const std::vector<std::string>& forwarded, const std::vector<std::string>& inputs,
              const BatchOptions& batch, bool quiet) {
  // Each file runs as the `ddtscale` front beside this program where there
  // is one, so that PNG to PNG starts without OpenImageIO (cli/front_main.cpp).
  std::error_code link_error;
  const fs::path self = fs::read_symlink("/proc/self/exe", link_error);
  const fs::path front = self.parent_path() / "ddtscale";
  const std::string program = !link_error && self.filename() != "ddtscale" && ::access(front.c_str(), X_OK) == 0
                                  ? front.string()
                                  : std::string("/proc/self/exe");
  const auto start = std::chrono::steady_clock::now();
  std::error_code ec;
  fs::create_directories(batch.outdir, ec);
  if (!fs::is_directory(batch.outdir, ec)) {
    std::cerr << "ddtscale: cannot create the output directory '" << batch.outdir << "'\n";
    return 1;
  }
  std::vector<Job> failed_early;
  const std::vector<std::string> files = expand_inputs(inputs, failed_early);

  // Plan: outputs, skips, and two inputs that would write the same output.
  std::vector<Job> jobs;
  std::map<std::string, std::string> output_of;
  long long skipped = 0;
  const std::string format = batch.format.empty() || batch.format[0] == '.' ? batch.format : "." + batch.format;
  for (const auto& file : files) {
    const fs::path in(file);
    const std::string ext = format.empty() ? in.extension().string() : format;
    const std::string output = (fs::path(batch.outdir) / (in.stem().string() + batch.suffix + ext)).string();
    if (const auto [it, added] = output_of.emplace(fs::weakly_canonical(output, ec).string(), file); !added) {
      failed_early.push_back({file, output, "its output " + output + " is also the output of " + it->second});
      continue;
    }
    if (!batch.overwrite && fs::exists(output, ec)) {
      ++skipped;
      continue;
    }
    jobs.push_back({file, output, ""});
  }

  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int parallel = std::max(1, std::min<int>(batch.jobs > 0 ? batch.jobs : cores, static_cast<int>(jobs.size())));
  std::vector<std::string> options = forwarded;
  options.push_back("--quiet");
  const auto threads_given = [](const std::string& option) { return option.rfind("--threads=", 0) == 0; };
  if (std::none_of(forwarded.begin(), forwarded.end(), threads_given)) {
    options.push_back("--threads");
    options.push_back(std::to_string(std::max(1, cores / parallel)));
  }

  ddt::Progress progress;
  progress.begin("files", static_cast<std::int64_t>(jobs.size()));
  std::unique_ptr<ddt::ProgressBar> bar;
  if (!quiet && ddt::ProgressBar::is_terminal(stderr)) bar = std::make_unique<ddt::ProgressBar>(progress, stderr);
  auto report = [&](const std::string& line) {
    if (bar) bar->print(line);
    else std::cerr << line << "\n";
  };
  long long failed = 0, done = 0;
  for (const Job& job : failed_early) {
    report("ddtscale: " + job.input + ": " + job.error);
    ++failed;
  }

  // Each file in its own process; its stderr in a temporary file, read when it ends.
  const fs::path logs = fs::temp_directory_path() / ("ddtscale-batch-" + std::to_string(::getpid()));
  fs::create_directories(logs, ec);
  struct Running {
    std::size_t job;
    std::string log;
  };
  std::map<pid_t, Running> running;
  std::size_t next = 0;
  auto finish = [&](pid_t pid, int status) {
    const Running r = running.at(pid);
    running.erase(pid);
    const Job& job = jobs[r.job];
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      ++done;
    } else {
      ++failed;
      std::string why = last_line(r.log);
      if (WIFSIGNALED(status)) why = "stopped by signal " + std::to_string(WTERMSIG(status));
      if (why.empty()) why = "failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
      report("ddtscale: " + job.input + ": " + why);
    }
    fs::remove(r.log, ec);
    progress.add(1);
  };
  while (next < jobs.size() || !running.empty()) {
    while (next < jobs.size() && static_cast<int>(running.size()) < parallel) {
      const Job& job = jobs[next];
      const std::string log = (logs / (std::to_string(next) + ".log")).string();
      std::vector<std::string> args = {"ddtscale", job.input, job.output};
      args.insert(args.end(), options.begin(), options.end());
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      posix_spawn_file_actions_t actions;
      posix_spawn_file_actions_init(&actions);
      posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
      pid_t pid = 0;
      const int err = ::posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
      posix_spawn_file_actions_destroy(&actions);
      if (err != 0) {
        ++failed;
        report("ddtscale: " + job.input + ": cannot start a process (" + std::strerror(err) + ")");
        progress.add(1);
      } else {
        running[pid] = {next, log};
      }
      ++next;
    }
    if (running.empty()) continue;
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid > 0 && running.count(pid)) finish(pid, status);
  }
  fs::remove_all(logs, ec);
  if (bar) bar->stop();
  if (!quiet) {
    char line[160];
    std::snprintf(line, sizeof line, "ddtscale: %lld done, %lld skipped, %lld failed, %.1f s", done, skipped, failed,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    std::cerr << line << "\n";
  }
  return failed > 0 ? 1 : 0;
}
