#pragma once
// ddt::InputStatistics — what the consistent reconstruction needs to know
// of the whole input when it sees only a band of it: each channel's range
// (the halo limit's bound for isolated dots) and the code grid of a
// quantized input (the straight edges' rounding allowance and smallest
// step). Bands, tiles and Dask blocks compute them per part and merge, so
// that every part decides as the whole image does.

#include "util/image.hpp"
#include "util/input_rows.hpp"
#include "util/progress.hpp"

#include <vector>

namespace ddt {

struct InputStatistics {
  std::vector<float> min, max;  // per channel
  // 1/255 when every sample is a multiple of it (8-bit input), else 1/65535
  // when every sample is a multiple of that (16-bit), else 0.
  double quantum = 0;
};

// Errors: throws ddt::Error for an empty image.
InputStatistics input_statistics(const Image& image);
// The whole source's, read top to bottom in chunks of rows (a stage
// "statistics" of the progress, when given). Throws the source's errors.
InputStatistics input_statistics(const RowSource& source, Progress* progress = nullptr);

// The statistics of the union of two parts of an image (same channels).
InputStatistics merge(const InputStatistics& a, const InputStatistics& b);

}  // namespace ddt
