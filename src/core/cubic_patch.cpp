#include "core/cubic_patch.hpp"

namespace ddt::core {

template <int D>
void cubic_patch(const std::array<Vec<D>, D + 1>& p, const double* z, const double* g, double* b) {
  for (int i = 0; i <= D; ++i) {
    b[i] = z[i];
    for (int j = 0; j <= D; ++j) {
      if (j == i) continue;
      double along = g[i * D] * (p[j][0] - p[i][0]);  // from the first term, as the 2D patch sums
      for (int k = 1; k < D; ++k) along += g[i * D + k] * (p[j][k] - p[i][k]);
      b[pair_control<D>(i, j)] = z[i] + along / 3.0;
    }
  }
  int t = (D + 1) + (D + 1) * D;
  for (int i = 0; i <= D; ++i)
    for (int j = i + 1; j <= D; ++j)
      for (int k = j + 1; k <= D; ++k) {
        const double edge_mean = (b[pair_control<D>(i, j)] + b[pair_control<D>(j, i)] + b[pair_control<D>(j, k)] +
                                  b[pair_control<D>(k, j)] + b[pair_control<D>(k, i)] + b[pair_control<D>(i, k)]) /
                                 6.0;
        const double vertex_mean = (z[i] + z[j] + z[k]) / 3.0;
        b[t++] = edge_mean + 0.5 * (edge_mean - vertex_mean);
      }
}

template <int D>
double eval_cubic(const double* b, const double* w) {
  double v = 0;
  for (int i = 0; i <= D; ++i) {
    const double wi2 = w[i] * w[i];
    v += b[i] * wi2 * w[i];
    for (int j = 0; j <= D; ++j)
      if (j != i) v += 3 * b[pair_control<D>(i, j)] * wi2 * w[j];
  }
  int t = (D + 1) + (D + 1) * D;
  for (int i = 0; i <= D; ++i)
    for (int j = i + 1; j <= D; ++j)
      for (int k = j + 1; k <= D; ++k) v += 6 * b[t++] * w[i] * w[j] * w[k];
  return v;
}

template void cubic_patch<1>(const std::array<Vec<1>, 2>&, const double*, const double*, double*);
template double eval_cubic<1>(const double*, const double*);
template void cubic_patch<2>(const std::array<Vec<2>, 3>&, const double*, const double*, double*);
template double eval_cubic<2>(const double*, const double*);
template void cubic_patch<3>(const std::array<Vec<3>, 4>&, const double*, const double*, double*);
template double eval_cubic<3>(const double*, const double*);
template void cubic_patch<4>(const std::array<Vec<4>, 5>&, const double*, const double*, double*);
template double eval_cubic<4>(const double*, const double*);

}  // namespace ddt::core
