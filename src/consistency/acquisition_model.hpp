#pragma once
// ddt::AcquisitionModel — how an input pixel was made from the continuous
// image, and the linear map that remakes the input from an output.
//
// A pixel is rarely a point sample: a camera, a renderer and the SR
// benchmark's low-resolution pixels are averages over a footprint. The
// consistent reconstruction (consistent_reconstruction.hpp) makes the
// output reproduce the input under this model.
//
//   point          input pixel j is the value at its centre (j + 0.5): the
//                  paper's interpolation, no correction
//   box            the average over the pixel's area [j, j + 1) (default)
//   gauss:SIGMA    the area average blurred by a Gaussian PSF of SIGMA
//                  input pixels (a sensor behind optics)
//   bicubic        MATLAB's antialiased imresize(hr, 1/s, 'bicubic'), the
//                  SR benchmark's low-resolution images
//
// Discrete form: an output of m samples on an axis of n input pixels is
// mapped back by weights w(j, X) with input pixel j = sum_X w(j, X) out[X],
// sum_X w(j, X) = 1 for every j; images are mapped separably (rows, then
// columns). Output pixel X covers [X n / m, (X + 1) n / m) in input units;
// for `box` w(j, X) is the exact overlap of that interval with [j, j + 1).

#include "ddtscale/options.hpp"
#include "util/image.hpp"

#include <string>
#include <utility>
#include <vector>

namespace ddt {

// The weights of one axis, by output sample: output X contributes
// weight[k] to input pixel pixel[k] for k in [first[X], first[X + 1]).
struct AxisWeights {
  std::vector<int> first;   // m + 1 offsets
  std::vector<int> pixel;   // input pixel ids
  std::vector<double> weight;
};

// Inputs: model (not point), n input pixels >= 1, m output samples >= 1.
AxisWeights axis_weights(const AcquisitionModel& model, int n, int m);

// The same weights by input pixel: for each of the n pixels, its
// (output sample, weight) pairs in output order.
std::vector<std::vector<std::pair<int, double>>> by_input_pixel(const AxisWeights& w, int n);

// The input the model predicts from `out`: in_width x in_height x
// out.channels, pixel j = sum over X, Y of wy(j_y, Y) wx(j_x, X) out(X, Y).
Image apply_acquisition(const AcquisitionModel& model, const Image& out, int in_width, int in_height);

// The same map with its axis weights computed once, in double, for a range
// of input rows (bands of rows read only the output rows they need).
class Acquisition {
 public:
  // Inputs: model not point; the input and output grids, each >= 1 x 1.
  Acquisition(const AcquisitionModel& model, int in_width, int in_height, int out_width, int out_height);

  // Input rows [first, end) (in_width * C values a row, interleaved, into
  // `in`, resized) from `out`, which holds output rows
  // [out_origin, out_origin + out.height) of the output grid, out_width
  // wide. Errors: throws ddt::Error when `out` lacks a row they read
  // (rows_read).
  void apply(const Image& out, int out_origin, int first, int end, std::vector<double>& in) const;

  // The output rows input rows [first, end) read: [first, end) of the result.
  std::pair<int, int> rows_read(int first, int end) const;
  // The rows of [first, end) whose output rows all lie in [out_first, out_end).
  std::pair<int, int> rows_covered(int out_first, int out_end, int first, int end) const;
  // How many input rows away, at most, lie the centres of the output rows
  // an input row reads.
  int reach() const { return reach_; }

 private:
  int in_width_, in_height_, out_width_, out_height_;
  AxisWeights wx_;
  std::vector<std::vector<std::pair<int, double>>> by_row_;  // input row -> (output row, weight)
  bool one_weight_per_column_;                                // every output column feeds one input pixel
  int reach_ = 0;

  template <int C>
  void add_columns(const float* p, double* row) const;
};

}  // namespace ddt
