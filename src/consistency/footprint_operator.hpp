#pragma once
// ddt::footprint_operator — the linear map from the vertex values of a
// piecewise-linear surface on a pixel-grid mesh to what the acquisition
// model makes of its rendering: the input pixels that surface predicts.
//
// The surface is the one render_mesh draws with the linear render: output
// pixel (X, Y) takes the linear interpolant at its centre
// ((X + 0.5) / sx, (Y + 0.5) / sy) in the triangle that owns it (exact
// orientation, ties broken by the (eps, eps^2) perturbation the rasterizer
// uses), and outside the open hull box (0.5, W - 0.5) x (0.5, H - 0.5) the
// value at the nearest hull point (the clamped centre, linear along the
// hull's unit edges). The interpolant is continuous, so which triangle owns
// a centre on an edge changes no value; the tie rule only makes every
// centre counted once.
//
// Inputs:
//   mesh       a valid Mesh2 whose points are the pixel centres of a
//              width x height grid, vertex y * width + x at (x + 0.5, y + 0.5)
//              (hull edges between grid neighbours, as any triangulation of
//              the full grid has)
//   out_width, out_height  the output grid (sx = out_width / width, ...)
//   model      not point
// Output: a width*height x width*height sparse matrix A (rows: input pixels
//   y * width + x; columns: vertices), CSR with rows sorted by column, so
//   that apply_acquisition(model, render_linear(v)) == A v up to rounding.
// Complexity: one pass over the output pixels (taps of the model each),
//   O(out pixels * taps_x * taps_y); memory O(nonzeros) + one int per
//   output pixel.

#include "consistency/acquisition_model.hpp"
#include "util/image.hpp"
#include "image/mesh.hpp"

#include <cstdint>
#include <vector>

namespace ddt {

struct SparseRows {
  int rows = 0, cols = 0;
  std::vector<std::int64_t> start;  // rows + 1
  std::vector<index_t> col;
  std::vector<float> weight;

  // y = A x for `channels` interleaved channels (x: cols * channels).
  void multiply(const std::vector<double>& x, std::vector<double>& y, int channels) const;
};

SparseRows footprint_operator(const Mesh2& mesh, int width, int height, int out_width, int out_height,
                              const AcquisitionModel& model);

// The owning triangle of every output pixel whose centre lies strictly
// inside the hull box (the rasterizer's exact tie rule), -1 for the rim:
// out_width * out_height ids, row-major. Same preconditions as above.
std::vector<index_t> pixel_owners(const Mesh2& mesh, int width, int height, int out_width, int out_height);

// footprint_operator from owners computed once (they also serve
// add_linear_surface).
SparseRows footprint_operator(const Mesh2& mesh, const std::vector<index_t>& owners, int width, int height,
                              int out_width, int out_height, const AcquisitionModel& model);

// Adds the piecewise-linear surface with vertex values `values` (#V by
// out.channels, interleaved) to `out` in place, as render_mesh's linear
// render draws it (up to rounding: the interpolant is continuous, so a
// centre on an edge has one value whichever triangle owns it).
void add_linear_surface(Image& out, const Mesh2& mesh, const std::vector<index_t>& owners, int width, int height,
                        const std::vector<double>& values);

}  // namespace ddt
