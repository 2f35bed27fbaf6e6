#include "command_line.hpp"

#include "util/error.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>

std::string one_line(std::string s) {
  s = s.substr(0, s.find('\n'));
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r')) s.pop_back();
  return s;
}

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv, const std::string& who,
                                      const std::string& hint) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    std::cerr << who << ": " << one_line(e.what()) << (hint.empty() ? "" : " (see " + hint + ")") << "\n";
    return 2;
  }
}

void parse_width_height(const std::string& text, const std::string& option, int lo, int hi, int& width,
                        int& height) {
  char extra = 0;
  int w = 0, h = 0;
  const int n = std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &extra);
  if (n == 1) h = w;
  if ((n != 1 && n != 2) || w < lo || h < lo || w > hi || h > hi)
    throw ddt::Error(option + " wants N or WxH between " + std::to_string(lo) + " and " + std::to_string(hi) +
                     ", got '" + text + "'");
  width = w, height = h;
}

namespace {
std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}
}  // namespace

double parse_ratio(const std::string& text, const std::string& option, double lo, double hi) {
  char extra = 0;
  double a = 0, b = 1;
  const int n = std::sscanf(text.c_str(), "%lf/%lf%c", &a, &b, &extra);
  const double value = a / b;
  if ((n != 1 && n != 2) || !(b > 0) || !std::isfinite(value) || !(value > lo) || value > hi)
    throw ddt::Error(option + " wants a number or a ratio A/B (e.g. 4, 2.5 or 60/24) in (" + number_text(lo) + ", " +
                     number_text(hi) + "], got '" + text + "'");
  return value;
}
