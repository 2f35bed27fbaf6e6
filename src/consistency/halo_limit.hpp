#pragma once
// ddt::HaloLimiter — overshoots beside edges removed from a consistent
// output without losing its consistency.
//
// Each footprint (the output pixels whose centres lie in input pixel
// (x, y)) is clamped to the range halo_bounds allows after a common shift,
// the one that keeps the footprint's mean: at integer scales under the box
// model that mean is the acquisition, so consistency is kept exactly;
// elsewhere nearly (consistent_reconstruction.cpp corrects the rest).
// docs/consistency.md has the measurements behind the bounds.

#include "consistency/footprints.hpp"
#include "consistency/input_statistics.hpp"
#include "util/image.hpp"

#include <utility>
#include <vector>

namespace ddt {

// The range an output pixel may take in footprint (x, y), channel c: that of
// the 3x3 input pixels around it. Where the pixel is the strict minimum of
// them it may hold a dark feature thinner than a pixel, whose truth is
// darker than any input pixel: the range reaches down to the 5x5 minimum,
// and down to the image's darkest input pixel (image_min) where the pixel
// is the strict minimum of the 5x5 too (an isolated dot); likewise above.
std::pair<float, float> halo_bounds(const Image& src, int x, int y, int c, float image_min, float image_max);

// The common shift t for which the mean of clamp(v + t, lo, hi) over
// `values` is `mean` (it grows with t, piecewise linearly: two Newton
// steps, then a bisection over the breakpoints and the exact value on the
// piece found). `mean` must lie in [lo, hi], lo <= hi; lo or hi may be
// infinite.
double mean_keeping_shift(const std::vector<float>& values, double mean, double lo, double hi);

// Clamps the footprints of `out` (a consistent output of `src`) as above,
// those of input rows [first_row, end_row) (end_row < 0: to the last): each
// footprint is read and written alone, so bands of rows give the whole
// image's result. `band` places src and out in the whole image (rows
// absolute); `statistics` are the whole input's. Returns the number of
// footprints and channels changed.
class HaloLimiter {
 public:
  HaloLimiter(const Image& src, const InputStatistics& statistics, const RowBand& band = {});
  long long limit(Image& out, int first_row = 0, int end_row = -1) const;

 private:
  const Image& src_;
  InputStatistics statistics_;
  RowBand band_;
};

}  // namespace ddt
