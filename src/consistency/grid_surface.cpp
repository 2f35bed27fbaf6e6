#include "consistency/grid_surface.hpp"

#include "util/error.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace ddt {

// One axis: n vertices, m output samples.
struct GridSurface::Axis {
  int n = 0, m = 0;
  // Output sample X takes (1 - frac) v[lower] + frac v[lower + 1] (frac 0
  // where lower is the last vertex).
  std::vector<int> lower;
  std::vector<double> frac;
  // B[j]: (vertex i, weight) pairs sorted by i, what input pixel j
  // acquires of the hat of vertex i.
  std::vector<std::vector<std::pair<int, double>>> rows;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;

  Axis(const AcquisitionModel& model, int n_, int m_) : n(n_), m(m_), lower(m_), frac(m_), rows(n_) {
    const double step = static_cast<double>(n) / m;
    for (int X = 0; X < m; ++X) {
      const double u = std::clamp((X + 0.5) * step, 0.5, n - 0.5) - 0.5;
      const int i = std::min(n - 1, static_cast<int>(u));
      lower[X] = i;
      frac[X] = i + 1 < n ? u - i : 0.0;
    }
    const AxisWeights w = axis_weights(model, n, m);
    auto add = [&](int j, int i, double value) {
      auto& row = rows[j];
      auto it = std::lower_bound(row.begin(), row.end(), i, [](const auto& e, int key) { return e.first < key; });
      if (it != row.end() && it->first == i) it->second += value;
      else row.insert(it, {i, value});
    };
    for (int X = 0; X < m; ++X)
      for (int k = w.first[X]; k < w.first[X + 1]; ++k) {
        add(w.pixel[k], lower[X], w.weight[k] * (1 - frac[X]));
        if (frac[X] != 0) add(w.pixel[k], lower[X] + 1, w.weight[k] * frac[X]);
      }
    std::vector<Eigen::Triplet<double>> entries;
    for (int j = 0; j < n; ++j)
      for (const auto& [i, value] : rows[j]) entries.emplace_back(j, i, value);
    Eigen::SparseMatrix<double> B(n, n);
    B.setFromTriplets(entries.begin(), entries.end());
    lu.compute(B);
    if (lu.info() != Eigen::Success)
      throw Error("the acquisition model " + to_string(model) + " cannot be inverted on an axis of " +
                  std::to_string(n) + " pixels");
  }
};

GridSurface::GridSurface(int W, int H, int out_w, int out_h, const AcquisitionModel& model)
    : width_(W), height_(H), out_width_(out_w), out_height_(out_h) {
  if (W < 1 || H < 1 || out_w < 1 || out_h < 1) throw Error("grid surface: empty grid");
  x_ = std::make_unique<Axis>(model, W, out_w);
  y_ = std::make_unique<Axis>(model, H, out_h);
}

GridSurface::~GridSurface() = default;

void GridSurface::acquire(const std::vector<double>& v, std::vector<double>& y, int C) const {
  const int W = width_, H = height_;
  const std::size_t row_size = static_cast<std::size_t>(W) * C;
  if (v.size() != row_size * H) throw Error("grid surface: values of another grid");
  // Along x, each row; then along y, rows combined whole.
  std::vector<double> along_x(v.size(), 0.0);
  tbb::parallel_for(0, H, [&](int iy) {
    const double* in = &v[iy * row_size];
    double* out = &along_x[iy * row_size];
    for (int jx = 0; jx < W; ++jx)
      for (const auto& [ix, w] : x_->rows[jx])
        for (int c = 0; c < C; ++c) out[jx * C + c] += w * in[ix * C + c];
  });
  y.assign(v.size(), 0.0);
  tbb::parallel_for(0, H, [&](int jy) {
    double* out = &y[jy * row_size];
    for (const auto& [iy, w] : y_->rows[jy]) {
      const double* in = &along_x[iy * row_size];
      for (std::size_t k = 0; k < row_size; ++k) out[k] += w * in[k];
    }
  });
}

void GridSurface::solve(const std::vector<double>& r, std::vector<double>& v, int C) const {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int W = width_, H = height_;
  const std::size_t row_size = static_cast<std::size_t>(W) * C;
  if (r.size() != row_size * H) throw Error("grid surface: values of another grid");
  v.assign(r.begin(), r.end());
  // G = By (x) Bx, so v = By^-1 R Bx^-T: each row solved along x (its C
  // channels are the right-hand sides) ...
  tbb::parallel_for(0, H, [&](int iy) {
    Eigen::Map<RowMajor> row(&v[iy * row_size], W, C);
    const Eigen::MatrixXd solved = x_->lu.solve(row);
    row = solved;
  });
  // ... then every (column, channel) along y, in blocks of right-hand sides.
  Eigen::Map<RowMajor> all(v.data(), H, static_cast<Eigen::Index>(row_size));
  const Eigen::Index block = 256;
  const Eigen::Index blocks = (static_cast<Eigen::Index>(row_size) + block - 1) / block;
  tbb::parallel_for(Eigen::Index(0), blocks, [&](Eigen::Index b) {
    const Eigen::Index first = b * block, count = std::min(block, static_cast<Eigen::Index>(row_size) - first);
    const Eigen::MatrixXd solved = y_->lu.solve(all.middleCols(first, count));
    all.middleCols(first, count) = solved;
  });
}

void GridSurface::add_to(Image& out, const std::vector<double>& values, int first_row, int end_row) const {
  const int W = width_, C = out.channels;
  if (out.width != out_width_ || out.height != out_height_ ||
      values.size() != static_cast<std::size_t>(W) * height_ * C)
    throw Error("grid surface: values or output of another grid");
  const Axis &ax = *x_, &ay = *y_;
  if (end_row < 0 || end_row > out.height) end_row = out.height;
  first_row = std::max(0, first_row);
  if (first_row >= end_row) return;
  tbb::parallel_for(first_row, end_row, [&](int Y) {
    // The two input rows this output row lies between, interpolated once.
    const double fy = ay.frac[Y];
    const double* r0 = &values[static_cast<std::size_t>(ay.lower[Y]) * W * C];
    const double* r1 = fy != 0 ? r0 + static_cast<std::size_t>(W) * C : r0;
    std::vector<double> row(static_cast<std::size_t>(W) * C);
    for (std::size_t i = 0; i < row.size(); ++i) row[i] = (1 - fy) * r0[i] + fy * r1[i];
    float* o = &out.pixels[out.index(0, Y)];
    for (int X = 0; X < out.width; ++X, o += C) {
      const double* p = &row[static_cast<std::size_t>(ax.lower[X]) * C];
      const double fx = ax.frac[X];
      if (fx != 0)
        for (int c = 0; c < C; ++c) o[c] += static_cast<float>((1 - fx) * p[c] + fx * p[C + c]);
      else
        for (int c = 0; c < C; ++c) o[c] += static_cast<float>(p[c]);
    }
  });
}

}  // namespace ddt
