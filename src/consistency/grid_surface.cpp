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
    factor(lu, 0, n, model);
  }

  // The system of rows and vertices [first, end), factored.
  template <class LU>
  void factor(LU& solver, int first, int end, const AcquisitionModel& model) const {
    std::vector<Eigen::Triplet<double>> entries;
    for (int j = first; j < end; ++j)
      for (const auto& [i, value] : rows[j])
        if (i >= first && i < end) entries.emplace_back(j - first, i - first, value);
    Eigen::SparseMatrix<double> B(end - first, end - first);
    B.setFromTriplets(entries.begin(), entries.end());
    solver.compute(B);
    if (solver.info() != Eigen::Success)
      throw Error("the acquisition model " + to_string(model) + " cannot be inverted on an axis of " +
                  std::to_string(end - first) + " pixels");
  }

  // Rows from the middle one to the last whose weight in the inverse is
  // above 1e-13 of the diagonal's: how far a row's value reaches.
  int inverse_reach() const {
    const int c = n / 2;
    Eigen::VectorXd impulse = Eigen::VectorXd::Zero(n);
    impulse[c] = 1;
    const Eigen::VectorXd column = lu.solve(impulse);
    const double floor = 1e-13 * std::abs(column[c]);
    int reach = 0;
    for (int i = 0; i < n; ++i)
      if (std::abs(column[i]) > floor) reach = std::max(reach, std::abs(i - c));
    return reach;
  }
};

GridSurface::GridSurface(int W, int H, int out_w, int out_h, const AcquisitionModel& model)
    : width_(W), height_(H), out_width_(out_w), out_height_(out_h) {
  if (W < 1 || H < 1 || out_w < 1 || out_h < 1) throw Error("grid surface: empty grid");
  x_ = std::make_unique<Axis>(model, W, out_w);
  y_ = std::make_unique<Axis>(model, H, out_h);
  model_ = model;
  window_rows_ = std::clamp(y_->inverse_reach() + 1, 2, 256);
  block_rows_ = std::max(32, 2 * window_rows_);
}

GridSurface::~GridSurface() = default;

void GridSurface::acquire(const std::vector<double>& v, std::vector<double>& y, int C, int first, int end) const {
  const int W = width_;
  if (end < 0) end = height_;
  const std::size_t row_size = static_cast<std::size_t>(W) * C;
  if (first < 0 || end > height_ || first > end || v.size() != row_size * (end - first))
    throw Error("grid surface: values of another grid");
  // Along x, each row; then along y, rows combined whole.
  std::vector<double> along_x(v.size(), 0.0);
  tbb::parallel_for(first, end, [&](int iy) {
    const double* in = &v[(iy - first) * row_size];
    double* out = &along_x[(iy - first) * row_size];
    for (int jx = 0; jx < W; ++jx)
      for (const auto& [ix, w] : x_->rows[jx])
        for (int c = 0; c < C; ++c) out[jx * C + c] += w * in[ix * C + c];
  });
  y.assign(v.size(), 0.0);
  tbb::parallel_for(first, end, [&](int jy) {
    double* out = &y[(jy - first) * row_size];
    for (const auto& [iy, w] : y_->rows[jy]) {
      if (iy < first || iy >= end) continue;
      const double* in = &along_x[(iy - first) * row_size];
      for (std::size_t k = 0; k < row_size; ++k) out[k] += w * in[k];
    }
  });
}

void GridSurface::solve(const std::vector<double>& r, std::vector<double>& v, int C, int first, int end) const {
  if (end < 0) end = height_;
  solve_rows(r, v, C, first, end, first, end);
}

void GridSurface::solve_rows(const std::vector<double>& r, std::vector<double>& v, int C, int first, int end,
                             int keep_first, int keep_end) const {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using Solver = Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>>;
  const int W = width_;
  const std::size_t row_size = static_cast<std::size_t>(W) * C;
  if (first < 0 || end > height_ || first >= end || r.size() != row_size * (end - first) || keep_first < first ||
      keep_end > end || keep_first >= keep_end)
    throw Error("grid surface: values of another grid");
  // G = By (x) Bx, so v = By^-1 R Bx^-T: along y block by block on each
  // block's window (canonical blocks of absolute rows, so that every band
  // cuts them alike), after each row of the windows is solved along x (its
  // C channels the right-hand sides).
  const int B = block_rows_, M = window_rows_;
  const int first_block = keep_first / B, end_block = (keep_end + B - 1) / B;
  auto window = [&](int k) { return std::pair{std::max(first, k * B - M), std::min(end, (k + 1) * B + M)}; };
  const int solved_first = window(first_block).first, solved_end = window(end_block - 1).second;
  const int rows = solved_end - solved_first;
  std::vector<double> along_x(r.begin() + static_cast<std::ptrdiff_t>(row_size * (solved_first - first)),
                              r.begin() + static_cast<std::ptrdiff_t>(row_size * (solved_end - first)));
  tbb::parallel_for(0, rows, [&](int iy) {
    Eigen::Map<RowMajor> row(&along_x[iy * row_size], W, C);
    const Eigen::MatrixXd solved = x_->lu.solve(row);
    row = solved;
  });
  std::vector<std::unique_ptr<Solver>> solvers(end_block - first_block);
  tbb::parallel_for(first_block, end_block, [&](int k) {
    const auto [a, b] = window(k);
    solvers[k - first_block] = std::make_unique<Solver>();
    y_->factor(*solvers[k - first_block], a, b, model_);
  });
  // Every (column, channel) a right-hand side, in groups of 256.
  v.assign(row_size * (keep_end - keep_first), 0.0);
  const Eigen::Map<const RowMajor> input(along_x.data(), rows, static_cast<Eigen::Index>(row_size));
  Eigen::Map<RowMajor> output(v.data(), keep_end - keep_first, static_cast<Eigen::Index>(row_size));
  const Eigen::Index group = 256;
  const Eigen::Index groups = (static_cast<Eigen::Index>(row_size) + group - 1) / group;
  tbb::parallel_for(Eigen::Index(0), groups * (end_block - first_block), [&](Eigen::Index task) {
    const int k = first_block + static_cast<int>(task / groups);
    const Eigen::Index col = (task % groups) * group, count = std::min(group, static_cast<Eigen::Index>(row_size) - col);
    const auto [a, b] = window(k);
    const Eigen::MatrixXd solved = solvers[k - first_block]->solve(input.block(a - solved_first, col, b - a, count));
    const int kept_first = std::max(keep_first, k * B), kept_end = std::min(keep_end, (k + 1) * B);
    output.block(kept_first - keep_first, col, kept_end - kept_first, count) =
        solved.middleRows(kept_first - a, kept_end - kept_first);
  });
}

void GridSurface::add_to(Image& out, const std::vector<double>& values, int first_row, int end_row, int out_origin,
                         int v_first) const {
  const int W = width_, C = out.channels;
  const std::size_t row_size = static_cast<std::size_t>(W) * C;
  if (out.width != out_width_ || values.size() % row_size != 0) throw Error("grid surface: values or output of another grid");
  const Axis &ax = *x_, &ay = *y_;
  if (end_row < 0) end_row = out_origin + out.height;
  first_row = std::max(out_origin, first_row);
  end_row = std::min(end_row, out_origin + out.height);
  if (first_row >= end_row) return;
  // Rows between vertex rows the values lack (at a band's cut) are left.
  const int v_end = v_first + static_cast<int>(values.size() / row_size);
  while (first_row < end_row && ay.lower[first_row] < v_first) ++first_row;
  while (end_row > first_row && ay.lower[end_row - 1] + (ay.frac[end_row - 1] != 0) >= v_end) --end_row;
  if (first_row >= end_row) return;
  tbb::parallel_for(first_row, end_row, [&](int Y) {
    // The two input rows this output row lies between, interpolated once.
    const double fy = ay.frac[Y];
    const double* r0 = &values[static_cast<std::size_t>(ay.lower[Y] - v_first) * row_size];
    const double* r1 = fy != 0 ? r0 + row_size : r0;
    std::vector<double> row(row_size);
    for (std::size_t i = 0; i < row.size(); ++i) row[i] = (1 - fy) * r0[i] + fy * r1[i];
    float* o = &out.pixels[out.index(0, Y - out_origin)];
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
