// libFuzzer target: the point-table reader of `ddtscale grid` (CSV, XYZ),
// with and without explicit columns and an input no-data value. Any input
// must give a table or a ddt::Error, nothing else.
#include "util/error.hpp"
#include "scattered/point_table.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (int variant = 0; variant < 3; ++variant) {
    ddt::PointReadOptions options;
    options.max_points = 100000;
    if (variant == 1) options.columns = {"x", "y", "3"};
    if (variant == 2) options.input_nodata = std::nan(""), options.float_values = true;
    std::istringstream in(text);
    try {
      ddt::PointTable table = ddt::parse_point_table(in, "fuzz.csv", options);
      // What the reader promises of a table it returns.
      if (table.channels < 1 || table.values.size() != table.points.size() * table.channels) __builtin_trap();
      for (const ddt::Point2& p : table.points)
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) __builtin_trap();
      ddt::merge_duplicate_points(table);
    } catch (const ddt::Error&) {
    }
  }
  return 0;
}
