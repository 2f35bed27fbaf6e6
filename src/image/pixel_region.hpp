#pragma once
// A rectangle of input pixels (--mesh-roi), parsed and checked before any
// work.

#include <string>

namespace ddt {

struct PixelRegion {
  int x = 0, y = 0, width = 0, height = 0;
};

// Parses "x,y,w,h"; throws ddt::Error naming the option on bad text or
// when x + w or y + h would not fit an int.
PixelRegion parse_region(const std::string& text);

// Throws when `roi` (width 0: the whole image) leaves a width x height
// image; called as soon as the input's size is known, before the work.
void check_region(const PixelRegion& roi, int width, int height);

}  // namespace ddt
