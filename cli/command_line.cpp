#include "command_line.hpp"

#include "util/error.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <numeric>
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

// "A" or "A/B", the whole text read.
bool read_ratio(const std::string& text, double& a, double& b) {
  int used = 0;
  b = 1;
  if (std::sscanf(text.c_str(), "%lf%n", &a, &used) != 1) return false;
  if (text[used] == '/') {
    int more = 0;
    if (std::sscanf(text.c_str() + used + 1, "%lf%n", &b, &more) != 1) return false;
    used += 1 + more;
  }
  return static_cast<std::size_t>(used) == text.size();
}
}  // namespace

std::string rate_text(const std::string& rate, const std::string& factor) {
  // Exact when both are whole numbers or ratios of them (decimals as tenths, hundredths...).
  auto fraction = [](const std::string& text, long long& num, long long& den) {
    double a = 0, b = 1;
    if (!read_ratio(text, a, b)) return false;
    long long scale = 1;
    while (a != std::floor(a) && scale < 1000000) a *= 10, scale *= 10;
    if (a != std::floor(a) || b != std::floor(b) || a > 1e12 || b > 1e12) return false;
    num = static_cast<long long>(a), den = static_cast<long long>(b) * scale;
    return den > 0;
  };
  long long n1 = 0, d1 = 1, n2 = 0, d2 = 1;
  if (fraction(rate, n1, d1) && fraction(factor, n2, d2) && n1 < (1LL << 31) && n2 < (1LL << 31) &&
      d1 < (1LL << 31) && d2 < (1LL << 31)) {
    long long num = n1 * n2, den = d1 * d2;
    const long long g = std::gcd(num, den);
    if (g > 0) num /= g, den /= g;
    return den == 1 ? std::to_string(num) : std::to_string(num) + "/" + std::to_string(den);
  }
  double a = 0, b = 1, c = 0, d = 1;
  read_ratio(rate, a, b), read_ratio(factor, c, d);
  char text[64];
  std::snprintf(text, sizeof text, "%.9g", a / b * c / d);
  return text;
}

double parse_ratio(const std::string& text, const std::string& option, double lo, double hi) {
  double a = 0, b = 1;
  const bool read = read_ratio(text, a, b);
  const double value = a / b;
  if (!read || !(b > 0) || !std::isfinite(value) || !(value > lo) || value > hi)
    throw ddt::Error(option + " wants a number or a ratio A/B (e.g. 4, 2.5 or 60/24) in (" + number_text(lo) + ", " +
                     number_text(hi) + "], got '" + text + "'");
  return value;
}
