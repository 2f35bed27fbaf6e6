#pragma once
// ddt::GridSurface — the bilinear surface on the pixel grid: what the
// acquisition model makes of its rendering, and the exact inverse of that.
//
// The consistent reconstruction (consistent_reconstruction.hpp) solves the
// part of its correction that the data-dependent mesh cannot carry on a
// well-conditioned surface. The bilinear (tensor-product hat) surface is
// separable, and so is every acquisition model, so its operator is the
// Kronecker product of two axis matrices:
//   G = By (x) Bx,  B[j][i] = sum over X of w(j, X) hat_i((X + 0.5) n / m)
// (w: the model's axis weights, acquisition_model.hpp), and G v = r is
// solved exactly, axis by axis, with a sparse LU of each n x n axis matrix
// (banded: a few entries a row): O(pixels) with no iteration, no matrix
// of the image's size, and no pixel loop at output resolution.
//
// The surface: output pixel (X, Y) takes the bilinear interpolant of the
// vertex values at its centre ((X + 0.5) / sx, (Y + 0.5) / sy), vertex
// y * width + x at (x + 0.5, y + 0.5); outside the samples' box
// [0.5, W - 0.5] x [0.5, H - 0.5] (the half-pixel rim) the value at the
// clamped centre, as the linear render draws its rim.
//
// Vectors hold width*height by C values, interleaved (pixel-major), or
// the rows [first, end) of the grid where a range is given.
//
// Bands: the inverse along y couples every row to every other, but its
// weights fall geometrically away from the diagonal (by about 0.17 a row
// for the box model). So the y solve is cut into canonical blocks of
// block_rows() rows, each solved on the window of window_rows() more rows
// each side (the system of the window's own rows): a row's value then
// depends on at most reach() rows either side, and a band of rows with
// that much margin solves its inner rows to the same bits as the whole
// image. The window is where the whole inverse has fallen to 1e-13 of its
// diagonal, so the blocks agree with the exact solve to rounding.

#include "consistency/acquisition_model.hpp"
#include "util/image.hpp"

#include <memory>
#include <vector>

namespace ddt {

class GridSurface {
 public:
  // Inputs: width, height >= 1 input pixels; out_width, out_height >= 1;
  //   model not point. Errors: throws ddt::Error for an empty grid or an
  //   axis matrix that is singular (a model that cannot be inverted).
  GridSurface(int width, int height, int out_width, int out_height, const AcquisitionModel& model);
  ~GridSurface();
  GridSurface(const GridSurface&) = delete;
  GridSurface& operator=(const GridSurface&) = delete;

  // y = G v: what the model acquires of the surface with vertex values v,
  // both on rows [first, end) (end < 0: to the last; rows of v outside the
  // range count as 0).
  void acquire(const std::vector<double>& v, std::vector<double>& y, int channels, int first = 0,
               int end = -1) const;
  // v with G v = r, both on rows [first, end): each block of rows solved on
  // its window, clipped to the range (exact up to rounding on the whole grid).
  void solve(const std::vector<double>& r, std::vector<double>& v, int channels, int first = 0, int end = -1) const;
  // The same solve of r (rows [first, end)), but only its rows [keep_first,
  // keep_end) computed, into v: the blocks that hold them, each on its
  // window clipped to [first, end). With reach() rows of r either side of
  // the kept rows (or the grid's border), those rows are the whole grid's.
  void solve_rows(const std::vector<double>& r, std::vector<double>& v, int channels, int first, int end,
                  int keep_first, int keep_end) const;
  // Adds the surface with vertex values v (rows [v_first, ...) of the grid)
  // to output rows [first_row, end_row) (end_row < 0: to the last), in
  // place; `out` holds output rows [out_origin, out_origin + out.height).
  // Output rows between vertex rows that v lacks are left as they are.
  void add_to(Image& out, const std::vector<double>& v, int first_row = 0, int end_row = -1, int out_origin = 0,
              int v_first = 0) const;

  int block_rows() const { return block_rows_; }
  int window_rows() const { return window_rows_; }
  // The rows either side whose residual a solved row depends on.
  int reach() const { return block_rows_ - 1 + window_rows_; }

 private:
  struct Axis;
  int width_, height_, out_width_, out_height_;
  AcquisitionModel model_;
  int block_rows_ = 0, window_rows_ = 0;
  std::unique_ptr<Axis> x_, y_;
};

}  // namespace ddt
