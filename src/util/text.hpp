#pragma once
// Small text helpers for names and messages: ASCII lower case, and a list
// joined by ", " (the valid choices an error message names).

#include <cctype>
#include <string>
#include <vector>

namespace ddt {

inline std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

inline std::string joined(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& item : items) s += (s.empty() ? "" : ", ") + item;
  return s;
}

}  // namespace ddt
