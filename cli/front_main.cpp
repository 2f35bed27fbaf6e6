// ddtscale — the command's front. The commonest jobs, a PNG enlarged into a
// PNG or an EXR, run here through libpng and OpenEXR alone
// (io/png_file.hpp, io/exr_file.hpp): this program does not load
// OpenImageIO, whose start takes 0.3 s and 130 MB. Every other command line
// (other formats, subcommands, --compare, --mesh, batches, --help, errors)
// is run again, unchanged, as ddtscale-full beside this program
// (cli/main.cpp), before anything is written. Both give the same files and
// messages.

#include "file_job.hpp"
#include "upscale_arguments.hpp"

#include "io/image_formats.hpp"
#include "util/allocator_tuning.hpp"
#include "util/error.hpp"
#include "util/file_names.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>

#include <unistd.h>

namespace {

[[noreturn]] void run_full(char** argv) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::string full = (ec ? std::filesystem::path(".") : self.parent_path()) / "ddtscale-full";
  ::execv(full.c_str(), argv);
  std::cerr << "ddtscale: cannot run " << full << ": " << std::strerror(errno) << "\n";
  std::exit(1);
}

bool has_extension(const std::string& path, const char* extension) {
  return ddt::lower_extension(path) == extension && path.find('%') == std::string::npos;
}

}  // namespace

int main(int argc, char** argv) {
  const UpscaleCommandLine line = parse_upscale_command_line(argc, argv);
  const UpscaleArguments& args = line.args;
  // An EXR only when streamed: its metadata may still hand the job on when
  // the output is created, which streaming does before the work.
  const bool exr = has_extension(args.output, ".exr") && !args.writing.no_stream;
  if (line.action != UpscaleCommandLine::Action::run || !has_extension(args.input, ".png") ||
      !(has_extension(args.output, ".png") || exr) || !args.compare.empty() || !args.mesh_view.empty())
    run_full(argv);
  ddt::tune_allocator(ddt::AllocatorUse::equal_bands);
  try {
    validate_arguments(args);
    return run_file_job(args);
  } catch (const ddt::NeedsOpenImageIO&) {
    run_full(argv);
  } catch (const ddt::Error&) {
    run_full(argv);  // its message, in ddtscale-full's words
  }
}
