#pragma once
// The extension of a path, lower case with its dot (".png"), which picks a
// format everywhere a file is read or written by its name.

#include <filesystem>
#include <string>

namespace ddt {

inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

}  // namespace ddt
