#include "util/size_limits.hpp"

#include "util/error.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include <unistd.h>

namespace ddt {

long long physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<long long>(pages) * page : 8LL << 30;
}

long long available_memory() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  long long kilobytes = 0;
  while (meminfo >> key >> kilobytes) {
    if (key == "MemAvailable:") return kilobytes * 1024;
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return physical_memory();
}

long long resident_memory() {
  std::ifstream statm("/proc/self/statm");
  long long size = 0, resident = 0;
  if (!(statm >> size >> resident)) return 0;
  const long page = ::sysconf(_SC_PAGE_SIZE);
  return page > 0 ? resident * page : 0;
}

long long parse_memory_size(const std::string& text) {
  const auto bad = [&] {
    return Error("'" + text + "' is not a memory size: give bytes, or a number with K, M, G or T (e.g. 2G)");
  };
  std::size_t used = 0;
  double number = 0;
  try {
    if (text.empty() || !(std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '.')) throw bad();
    number = std::stod(text, &used);
  } catch (const std::exception&) {
    throw bad();
  }
  std::string unit = text.substr(used);
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();
  if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();
  const std::string units = "KMGT";
  double bytes = number;
  if (unit == "B" || unit.empty()) {
    if (number != std::floor(number)) throw bad();
  } else if (unit.size() == 1 && units.find(unit[0]) != std::string::npos) {
    bytes = std::ldexp(number, 10 * static_cast<int>(units.find(unit[0]) + 1));
  } else {
    throw bad();
  }
  if (!(bytes >= 1) || bytes > std::ldexp(1.0, 62)) throw bad();
  return static_cast<long long>(bytes);
}

long long default_max_input_pixels() { return physical_memory() / 32; }
long long default_max_input_voxels() { return physical_memory() / 1024; }
long long default_max_input_points() { return physical_memory() / 1024; }

void check_size_limit(const std::string& what, const std::string& size, long long count, long long limit,
                      const std::string& option) {
  if (count >= 0 && count <= limit) return;
  // The value that allows it, where the count is one (not a header's
  // overflowing claim).
  // Past what any machine holds (2^40: a thousand gigapixels or
  // gigavoxels) the hint would only mislead.
  const std::string allow = count >= 0 && count <= (1LL << 40)
                                ? "; give " + option + " " + std::to_string(count) + " to allow it"
                                : "";
  throw Error(what + " " + size + " exceeds " + option + " " + std::to_string(limit) + allow);
}

long long checked_product(std::initializer_list<long long> sizes) {
  long long product = 1;
  for (long long s : sizes)
    if (s < 0 || __builtin_mul_overflow(product, s, &product)) return -1;
  return product;
}

void check_memory_fits(const std::string& job, double bytes) {
  const long long available = available_memory();
  if (bytes <= static_cast<double>(available)) return;
  char line[64];
  std::snprintf(line, sizeof line, " needs at least %.0f MB of memory, %lld MB are available", bytes / 1048576.0,
                available / 1048576);
  throw Error(job + line);
}

}  // namespace ddt
