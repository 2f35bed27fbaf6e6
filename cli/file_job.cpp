#include "file_job.hpp"

#include "io/image_formats.hpp"
#include "pipeline/file_upscale.hpp"
#include "util/error.hpp"
#include "util/thread_limit.hpp"

#include <iostream>
#include <new>

#include <unistd.h>

JobConsole::JobConsole(bool quiet, bool verbose) : verbose_(verbose), bar_out_(nullptr, &std::fclose) {
  // The bar draws on its own copy of the terminal's descriptor: image I/O
  // points stderr at /dev/null while libraries read and write
  // (src/io/image_io.cpp), and the bar goes on through the write stage.
  if (quiet || !ddt::ProgressBar::is_terminal(stderr)) return;
  const int terminal = ::dup(STDERR_FILENO);
  if (terminal >= 0) bar_out_.reset(::fdopen(terminal, "w"));
  if (terminal >= 0 && !bar_out_) ::close(terminal);
  if (!bar_out_) return;
  std::setvbuf(bar_out_.get(), nullptr, _IONBF, 0);
  bar_ = std::make_unique<ddt::ProgressBar>(progress_, bar_out_.get());
}

JobConsole::~JobConsole() = default;

void JobConsole::log(const std::string& line) {
  if (!verbose_) return;
  if (bar_) bar_->print(line);
  else std::cerr << line << "\n";
}

void JobConsole::stop() {
  if (bar_) bar_->stop();
}

int report_failure(const std::function<int()>& job) {
  try {
    return job();
  } catch (const ddt::NeedsOpenImageIO&) {
    throw;
  } catch (const ddt::Error& e) {
    std::cerr << "ddtscale: " << e.what() << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << "ddtscale: out of memory (try a smaller output or --max-pixels)\n";
  } catch (const std::exception& e) {
    std::cerr << "ddtscale: " << e.what() << "\n";
  }
  return 1;
}

int run_file_job(UpscaleArguments args) {
  return report_failure([&] {
    ddt::check_output_path(args.output, args.input);
    // Both cores unless --threads says otherwise.
    args.threads = ddt::usable_threads(args.threads);
    const auto thread_limit = ddt::limit_threads(args.threads);
    JobConsole console(args.quiet, args.verbose);
    ddt::UpscaleOptions options = upscale_options(args);
    if (args.verbose) options.log = [&console](const std::string& line) { console.log(line); };
    options.progress = &console.progress();
    ddt::FileUpscaleJob job{args.input, args.output, size_request(args), options, args.writing.encode,
                            !args.writing.no_stream, args.max_input_pixels, {}};
    if (!args.quiet) job.warn = [](const std::string& line) { std::cerr << "ddtscale: warning: " << line << "\n"; };
    const ddt::FileUpscaleResult result = ddt::upscale_file(std::move(job));
    console.stop();
    if (!args.quiet && !args.verbose) std::cerr << args.output << ": " << result.width << "x" << result.height << "\n";
    return 0;
  });
}
