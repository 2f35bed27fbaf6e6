#include "io/image_formats.hpp"
#include "io/safe_file.hpp"

#include <filesystem>
#include <system_error>

#include <unistd.h>

namespace fs = std::filesystem;

namespace ddt {

void check_output_path(const std::string& output, const std::string& input, bool image_format) {
  std::error_code ec;
  if (output.empty()) throw Error("no output file given");
  if (!input.empty()) check_not_an_input(output, {input});
  if (!input.empty() && fs::weakly_canonical(output, ec) == fs::weakly_canonical(input, ec))
    throw Error("output '" + output + "' is the input file; refusing to overwrite it");
  const fs::path target = resolve_output_link(output);  // a symlink: the file it points to is replaced
  if (fs::is_directory(target, ec)) throw Error("output '" + output + "' is a directory");
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) throw Error("output directory '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0) throw Error("output directory '" + dir.string() + "' is not writable");
  if (!image_format) return;
  if (output_format_name(output).empty()) throw Error("cannot write '" + output + "': no image format for extension '" +
                          fs::path(output).extension().string() + "'");
}

}  // namespace ddt
