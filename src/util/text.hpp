#pragma once
// Small text helpers for names and messages: ASCII lower case, a list
// joined by ", " (the valid choices an error message names), and the first
// line of a library's message (our errors are one line).

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

inline std::string first_line(std::string s) {
  auto trim = [&s] {
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  };
  trim();
  s = s.substr(0, s.find('\n'));
  trim();
  return s;
}

}  // namespace ddt
