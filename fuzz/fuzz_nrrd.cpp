// libFuzzer target: the NRRD reading path (read_volume: header, detached
// data files, encodings, the size checks). The input is a header, written
// as in.nhdr, optionally followed by "\n@@data@@\n" and the bytes of a data
// file written beside it as d.raw (a header names it: `data file: d.raw`).
// Any input must give a volume or a ddt::Error, nothing else.
#include "util/error.hpp"
#include "io/volume_io.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "ddtscale-fuzz-nrrd-XXXXXX").string();
    return std::filesystem::path(mkdtemp(pattern.data()));
  }();
  return dir;
}

void write(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string separator = "\n@@data@@\n";
  const std::size_t cut = input.find(separator);
  const std::filesystem::path header = scratch() / "in.nhdr", data_file = scratch() / "d.raw";
  write(header, input.substr(0, cut));
  write(data_file, cut == std::string::npos ? std::string() : input.substr(cut + separator.size()));
  ddt::VolumeReadOptions options;
  options.max_voxels = 1 << 22;
  try {
    const ddt::VolumeFile file = ddt::read_volume(header.string(), options);
    if (file.volume.voxel_count() > std::size_t(1) << 22) __builtin_trap();
  } catch (const ddt::Error&) {
  }
  return 0;
}
