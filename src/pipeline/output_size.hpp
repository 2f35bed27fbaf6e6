#pragma once
// ddt::output_size — the output size of an enlargement from a scale or a
// width and/or height, as the command line (`--scale`, `--width`,
// `--height`, `--max-pixels`) and the Python module take them.
//
// Rules: give a scale, or a width and/or a height (the missing one follows
// the aspect ratio, rounded, at least 1), never both; the output may not
// have more than max_pixels pixels.
// Errors: throws ddt::Error with the command line's one-line messages.

#include <optional>

namespace ddt {

struct SizeRequest {
  std::optional<double> scale;
  std::optional<int> width, height;
  long long max_pixels = 0;  // > 0
};

// Inputs: the request, the input's width and height (>= 1).
// Outputs: out_width, out_height (>= 1).
void output_size(const SizeRequest& request, int in_width, int in_height, int& out_width, int& out_height);

}  // namespace ddt
