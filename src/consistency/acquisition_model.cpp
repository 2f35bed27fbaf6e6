#include "consistency/acquisition_model.hpp"

#include "util/error.hpp"
#include "eval/matlab_resize.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace ddt {
namespace {

using Kind = AcquisitionModel::Kind;

// Input pixel j -> (output sample, weight) lists, one per j.
using ByPixel = std::vector<std::vector<std::pair<int, double>>>;

ByPixel box_weights(int n, int m) {
  // In units of 1/m input pixels output X covers [X n, (X + 1) n) and input
  // pixel j covers [j m, (j + 1) m): the overlaps are integers, exact.
  ByPixel by(n);
  for (int X = 0; X < m; ++X) {
    const long long a = static_cast<long long>(X) * n, b = a + n;
    for (long long j = a / m; j < n && j * m < b; ++j) {
      const long long lo = std::max(a, j * m), hi = std::min(b, (j + 1) * m);
      if (hi > lo) by[j].push_back({X, static_cast<double>(hi - lo) / m});
    }
  }
  return by;
}

// The pixel's box [-1/2, 1/2] convolved with a Gaussian of `sigma`, at t.
double blurred_box(double t, double sigma) {
  const double k = 1 / (sigma * std::sqrt(2.0));
  return 0.5 * (std::erf((t + 0.5) * k) - std::erf((t - 0.5) * k));
}

ByPixel gauss_weights(int n, int m, double sigma) {
  const double reach = 0.5 + 4 * sigma;  // input pixels either side of a centre
  const double step = static_cast<double>(n) / m;
  ByPixel by(n);
  for (int j = 0; j < n; ++j) {
    const double c = j + 0.5;
    const int X0 = std::max(0, static_cast<int>(std::floor((c - reach) / step)));
    const int X1 = std::min(m - 1, static_cast<int>(std::ceil((c + reach) / step)));
    double sum = 0;
    for (int X = X0; X <= X1; ++X) {
      const double w = blurred_box((X + 0.5) * step - c, sigma);
      if (w > 0) by[j].push_back({X, w}), sum += w;
    }
    for (auto& [X, w] : by[j]) w /= sum;  // renormalized where the border cuts the PSF
  }
  return by;
}

ByPixel bicubic_weights(int n, int m) {
  const MatlabTaps t = matlab_taps(m, n);
  ByPixel by(n);
  for (int j = 0; j < n; ++j) {
    auto& list = by[j];
    for (int k = 0; k < t.taps; ++k) {
      const std::size_t slot = static_cast<std::size_t>(j) * t.taps + k;
      if (t.weight[slot] == 0) continue;
      auto it = std::find_if(list.begin(), list.end(), [&](const auto& e) { return e.first == t.index[slot]; });
      if (it == list.end()) list.push_back({t.index[slot], t.weight[slot]});
      else it->second += t.weight[slot];  // a tap mirrored onto one already there
    }
  }
  return by;
}

}  // namespace

AcquisitionModel parse_acquisition_model(const std::string& text) {
  AcquisitionModel model;
  if (text == "point") model.kind = Kind::point;
  else if (text == "box") model.kind = Kind::box;
  else if (text == "bicubic") model.kind = Kind::bicubic;
  else if (text.rfind("gauss:", 0) == 0) {
    const std::string number = text.substr(6);
    char* end = nullptr;
    const double sigma = number.empty() ? 0 : std::strtod(number.c_str(), &end);
    if (number.empty() || *end != '\0' || !std::isfinite(sigma) || sigma <= 0 || sigma > 100)
      throw Error("--model gauss:SIGMA needs SIGMA in input pixels, a number in (0, 100], got '" + number + "'");
    model.kind = Kind::gauss;
    model.sigma = sigma;
  } else {
    throw Error("unknown acquisition model '" + text + "' (expected point, box, gauss:SIGMA or bicubic)");
  }
  return model;
}

std::string to_string(const AcquisitionModel& model) {
  switch (model.kind) {
    case Kind::point: return "point";
    case Kind::box: return "box";
    case Kind::bicubic: return "bicubic";
    case Kind::gauss: {
      char text[48];
      std::snprintf(text, sizeof text, "gauss:%g", model.sigma);
      return text;
    }
  }
  return "box";
}

std::vector<std::string> acquisition_model_names() { return {"box", "gauss:SIGMA", "bicubic", "point"}; }

AxisWeights axis_weights(const AcquisitionModel& model, int n, int m) {
  if (n < 1 || m < 1) throw Error("axis_weights: empty axis");
  ByPixel by;
  switch (model.kind) {
    case Kind::box: by = box_weights(n, m); break;
    case Kind::gauss: by = gauss_weights(n, m, model.sigma); break;
    case Kind::bicubic: by = bicubic_weights(n, m); break;
    case Kind::point: throw Error("axis_weights: the point model has no footprint");
  }
  // Transpose to output order.
  AxisWeights w;
  w.first.assign(m + 1, 0);
  for (const auto& list : by)
    for (const auto& e : list) ++w.first[e.first + 1];
  for (int X = 0; X < m; ++X) w.first[X + 1] += w.first[X];
  w.pixel.resize(w.first[m]);
  w.weight.resize(w.first[m]);
  std::vector<int> fill(w.first.begin(), w.first.end() - 1);
  for (int j = 0; j < n; ++j)
    for (const auto& [X, weight] : by[j]) {
      w.pixel[fill[X]] = j;
      w.weight[fill[X]++] = weight;
    }
  return w;
}

std::vector<std::vector<std::pair<int, double>>> by_input_pixel(const AxisWeights& w, int n) {
  std::vector<std::vector<std::pair<int, double>>> by(n);
  const int m = static_cast<int>(w.first.size()) - 1;
  for (int X = 0; X < m; ++X)
    for (int k = w.first[X]; k < w.first[X + 1]; ++k) by[w.pixel[k]].push_back({X, w.weight[k]});
  return by;
}

namespace {

bool one_weight_each(const AxisWeights& w) {
  for (std::size_t X = 0; X + 1 < w.first.size(); ++X)
    if (w.first[X + 1] - w.first[X] != 1) return false;
  return true;
}

}  // namespace

Acquisition::Acquisition(const AcquisitionModel& model, int in_width, int in_height, int out_width, int out_height)
    : in_width_(in_width),
      in_height_(in_height),
      out_width_(out_width),
      out_height_(out_height),
      wx_(axis_weights(model, in_width, out_width)),
      by_row_(by_input_pixel(axis_weights(model, in_height, out_height), in_height)),
      one_weight_per_column_(one_weight_each(wx_)) {
  const double step = static_cast<double>(in_height) / out_height;
  for (int jy = 0; jy < in_height; ++jy)
    for (const auto& e : by_row_[jy]) {
      const int centre_row = std::clamp(static_cast<int>((e.first + 0.5) * step), 0, in_height - 1);
      reach_ = std::max(reach_, std::abs(centre_row - jy));
    }
}

// The general loop's additions in its order, so the same bits; with the
// channel count known and one weight a column (the box model at integer
// scales) the compiler unrolls it.
template <int C>
void Acquisition::add_columns(const float* p, double* row) const {
  for (int X = 0; X < out_width_; ++X, p += C) {
    double* q = row + static_cast<std::size_t>(wx_.pixel[X]) * C;
    const double w = wx_.weight[X];
    for (int c = 0; c < C; ++c) q[c] += w * p[c];
  }
}

std::pair<int, int> Acquisition::rows_covered(int out_first, int out_end, int first, int end) const {
  auto covered = [&](int jy) {
    const auto [lo, hi] = rows_read(jy, jy + 1);
    return lo >= hi || (lo >= out_first && hi <= out_end);
  };
  while (first < end && !covered(first)) ++first;
  while (end > first && !covered(end - 1)) --end;
  return {first, end};
}

std::pair<int, int> Acquisition::rows_read(int first, int end) const {
  int lo = out_height_, hi = 0;
  for (int jy = std::max(0, first); jy < std::min(end, in_height_); ++jy)
    for (const auto& e : by_row_[jy]) lo = std::min(lo, e.first), hi = std::max(hi, e.first + 1);
  return {std::min(lo, hi), hi};
}

void Acquisition::apply(const Image& out, int out_origin, int first, int end, std::vector<double>& in) const {
  const int C = out.channels;
  if (first < 0 || end > in_height_ || first > end || out.width != out_width_)
    throw Error("acquisition: rows or image of another grid");
  const auto [lo, hi] = rows_read(first, end);
  if (lo < hi && (lo < out_origin || hi > out_origin + out.height))
    throw Error("acquisition: the output rows do not cover the input rows");
  const std::size_t row_size = static_cast<std::size_t>(in_width_) * C;
  in.assign(row_size * (end - first), 0.0);
  // Each input row from its output rows, one row of sums at a time (memory
  // of one input row per thread, not of an intermediate image).
  tbb::parallel_for(first, end, [&](int jy) {
    double* acc = &in[row_size * (jy - first)];
    std::vector<double> row(row_size);
    for (const auto& [Y, wrow] : by_row_[jy]) {
      std::fill(row.begin(), row.end(), 0.0);
      const float* p = &out.pixels[out.index(0, Y - out_origin)];
      switch (one_weight_per_column_ ? C : 0) {
        case 1: add_columns<1>(p, row.data()); break;
        case 3: add_columns<3>(p, row.data()); break;
        case 4: add_columns<4>(p, row.data()); break;
        default:
          for (int X = 0; X < out.width; ++X, p += C)
            for (int k = wx_.first[X]; k < wx_.first[X + 1]; ++k) {
              double* q = &row[static_cast<std::size_t>(wx_.pixel[k]) * C];
              for (int c = 0; c < C; ++c) q[c] += wx_.weight[k] * p[c];
            }
      }
      for (std::size_t i = 0; i < row_size; ++i) acc[i] += wrow * row[i];
    }
  });
}

Image apply_acquisition(const AcquisitionModel& model, const Image& out, int in_width, int in_height) {
  std::vector<double> values;
  Acquisition(model, in_width, in_height, out.width, out.height).apply(out, 0, 0, in_height, values);
  Image in(in_width, in_height, out.channels);
  std::transform(values.begin(), values.end(), in.pixels.begin(), [](double v) { return static_cast<float>(v); });
  return in;
}

}  // namespace ddt
