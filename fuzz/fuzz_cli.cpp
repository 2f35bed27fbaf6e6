// libFuzzer target: the image command's command line (cli/upscale_arguments.hpp)
// parsed and validated in-process, then sized for a few input sizes as the
// run would from a header. The input is the argument list, one argument a
// line (argv[0] "ddtscale" is added). Nothing here runs a job, reads or
// writes a file. Any input must end in one of the parser's actions, and every
// refusal must be a ddt::Error of one non-empty line; anything else (another
// exception, a crash, a sanitizer report) is a finding.
#include "upscale_arguments.hpp"

#include "image/mesh_view.hpp"
#include "io/image_io.hpp"
#include "pipeline/file_upscale.hpp"
#include "pipeline/output_size.hpp"
#include "util/error.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace {

void require(bool condition) {
  if (!condition) __builtin_trap();
}

bool one_line(const std::string& text) { return !text.empty() && text.find('\n') == std::string::npos; }

void check_refusal(const ddt::Error& e) { require(one_line(e.what())); }

// What the run computes once it knows the input's header.
void size_job(const UpscaleArguments& args, int in_w, int in_h, int channels) {
  int out_w = 0, out_h = 0;
  try {
    ddt::output_size(size_request(args), in_w, in_h, out_w, out_h);
  } catch (const ddt::Error& e) {
    check_refusal(e);
    return;
  }
  require(out_w >= 1 && out_h >= 1 && double(out_w) * out_h <= double(args.max_pixels));
  const ddt::UpscaleOptions options = upscale_options(args);
  for (const bool streamed : {false, true}) {
    const double bytes = ddt::upscale_job_bytes(in_w, in_h, channels, out_w, out_h, options, streamed);
    require(std::isfinite(bytes) && bytes > 0);
  }
  if (!args.mesh_roi.empty()) {
    try {
      ddt::check_region(ddt::parse_region(args.mesh_roi), in_w, in_h);
    } catch (const ddt::Error& e) {
      check_refusal(e);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> tokens = {"ddtscale"};
  std::string token;
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == '\n') {
      tokens.push_back(token);
      token.clear();
    } else {
      token += static_cast<char>(data[i]);
    }
  }
  if (!token.empty()) tokens.push_back(token);
  std::vector<const char*> argv;
  for (const auto& t : tokens) argv.push_back(t.c_str());
  argv.push_back(nullptr);

  const UpscaleCommandLine line = parse_upscale_command_line(static_cast<int>(tokens.size()), argv.data());
  using Action = UpscaleCommandLine::Action;
  switch (line.action) {
    case Action::help:
      require(!line.text.empty());
      return 0;
    case Action::list_costs:
    case Action::version:
      return 0;
    case Action::usage_error:
      require(one_line(line.text));
      return 0;
    case Action::batch:
      require(!line.batch.outdir.empty() && !line.batch_inputs.empty());
      return 0;
    case Action::run:
      break;
  }
  try {
    validate_arguments(line.args);
  } catch (const ddt::Error& e) {
    check_refusal(e);
    return 0;
  }
  const int sizes[][3] = {{1, 1, 1}, {7, 5, 3}, {640, 480, 4}, {65535, 2, 2}, {46341, 46341, 1}};
  for (const auto& s : sizes) size_job(line.args, s[0], s[1], s[2]);
  return 0;
}
