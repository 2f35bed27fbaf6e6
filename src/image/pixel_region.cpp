#include "image/pixel_region.hpp"

#include "util/error.hpp"

#include <charconv>
#include <limits>
#include <system_error>

namespace ddt {

PixelRegion parse_region(const std::string& text) {
  // Four integers with from_chars (sscanf's %d overflows silently), and
  // x + w, y + h representable, so later arithmetic cannot overflow.
  const std::string wanted = "--mesh-roi wants x,y,w,h with x, y >= 0 and w, h > 0, got '" + text + "'";
  long long v[4] = {};
  const char* p = text.data();
  const char* end = text.data() + text.size();
  for (int k = 0; k < 4; ++k) {
    if (k > 0) {
      if (p == end || *p != ',') throw Error(wanted);
      ++p;
    }
    const auto [next, ec] = std::from_chars(p, end, v[k]);
    if (ec != std::errc() || next == p) throw Error(wanted);
    p = next;
  }
  if (p != end || v[0] < 0 || v[1] < 0 || v[2] <= 0 || v[3] <= 0) throw Error(wanted);
  constexpr long long limit = std::numeric_limits<int>::max();
  if (v[0] + v[2] > limit || v[1] + v[3] > limit) throw Error("--mesh-roi '" + text + "' is too large");
  return {static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2]), static_cast<int>(v[3])};
}

void check_region(const PixelRegion& roi, int width, int height) {
  if (roi.width == 0) return;
  if (static_cast<long long>(roi.x) + roi.width > width || static_cast<long long>(roi.y) + roi.height > height)
    throw Error("--mesh-roi " + std::to_string(roi.x) + "," + std::to_string(roi.y) + "," + std::to_string(roi.width) +
                "," + std::to_string(roi.height) + " leaves the " + std::to_string(width) + "x" +
                std::to_string(height) + " image");
}

}  // namespace ddt
