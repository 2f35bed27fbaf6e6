#pragma once
// ddt::render_step_edges — footprints that straddle one straight step edge
// drawn as that edge, box-filtered at output resolution.
//
// Under the box model an input pixel crossed by a straight edge between two
// flat regions is a + (b - a) x (the share of its area on b's side): its
// value fixes where the edge passes inside it, to a fraction of a pixel,
// which no interpolant through the pixel averages can show (its rise is
// about a pixel wide). Where the 3x3 input pixels around a footprint are
// explained by one straight edge between two levels (per channel a_c, b_c;
// one line for all channels) within `tolerance` of the step, the
// footprint's output pixels take that edge's exact coverage of their own
// area; then a common shift per channel, clamped to the 3x3 range, keeps
// the footprint's mean (the acquisition at integer scales). Elsewhere the
// output is left as it is: texture, corners, thin lines and smooth
// gradients do not fit one edge and keep the consistent reconstruction.
//
// The fit (per footprint): the line's normal from the Sobel gradient of
// the channel with the largest step, its offset from the centre pixel's
// share; then Levenberg-Marquardt over (angle, offset) with the levels
// solved by least squares for each trial line (variable projection).
//
// Samples quantized to 8 or 16 bits carry up to half a code value of
// rounding, which the misfits allow for.
//
// Inputs:
//   out   the output, out.width x out.height x C (changed in place)
//   src   the input, width x height x C, the box model's acquisition of out
// Returns: the number of footprints drawn as edges.
// Complexity: O(input pixels) fits, most rejected after one evaluation;
//   O(output pixels) for those drawn.

#include "consistency/footprints.hpp"
#include "consistency/input_statistics.hpp"
#include "util/image.hpp"

namespace ddt {

struct StepEdgeOptions {
  double tolerance = 0.02;  // largest misfit of any of the 3x3 pixels, as a share of the step
  // Smallest step worth drawing, in input code values where the input is
  // quantized (8 or 16 bits: every sample a multiple of 1/255 or 1/65535;
  // half a code value is then added to every misfit allowed), else as a
  // share of the image's range.
  double min_step_codes = 6;
  double min_step_share = 1e-3;
  // Largest misfit of the fitted edge over the 5x5 pixels, as a share of
  // the step: loose enough for a curved edge (a circle of radius r strays
  // 3 / r pixels from its tangent there), tight enough to turn away a
  // second feature within two pixels (the far side of a thin line).
  double reach_tolerance = 0.25;
};

// The footprints of input rows [first_row, end_row) (end_row < 0: to the
// last); each is read and written alone, so bands of rows give the whole
// image's result. The smallest step and the rounding allowance come from
// the whole input's statistics; `band` places src and out in the whole
// image (rows absolute, positions the whole image's).
class StepEdgeRenderer {
 public:
  StepEdgeRenderer(const Image& src, const InputStatistics& statistics, const RowBand& band = {},
                   const StepEdgeOptions& options = {});
  long long render(Image& out, int first_row = 0, int end_row = -1) const;

 private:
  const Image& src_;
  RowBand band_;
  StepEdgeOptions options_;
  double min_step_ = 0, rounding_ = 0;
};

long long render_step_edges(Image& out, const Image& src, const StepEdgeOptions& options = {});

// The share of a rectangle (its extents along the edge's normal p = w |nx|
// and q = h |ny|) on the normal's side of a straight edge passing at signed
// distance s from the rectangle's centre (s > 0: the centre is on that
// side). Exact: the integral of the trapezoid that convolves two boxes.
double rectangle_coverage(double s, double p, double q);

}  // namespace ddt
