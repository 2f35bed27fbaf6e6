#pragma once
// The extension of a path, lower case with its dot (".png"), which picks a
// format everywhere a file is read or written by its name.

#include "util/text.hpp"

#include <filesystem>
#include <string>

namespace ddt {

inline std::string lower_extension(const std::string& path) {
  return lower(std::filesystem::path(path).extension().string());
}

}  // namespace ddt
