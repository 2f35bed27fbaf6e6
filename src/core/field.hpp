#pragma once
// ddt::core::SimplexField<D> — what the costs read of one D-simplex: its
// content and, per value channel, the gradient of the linear interpolant
// of the vertex values (simplex_content<D> and simplex_gradient<D> of
// costs.hpp, the one place both are written).
//
// Inputs: points of the mesh, values #V by K (row-major), the cell's D + 1
// vertex ids (any orientation: the content is unsigned), K in
// 1..max_cost_channels. Gradients are computed only when asked for (the
// simplex-weight costs read the content alone).

#include "core/simplex_mesh.hpp"
#include "core/costs.hpp"

#include <Eigen/Dense>

namespace ddt::core {

template <int D>
struct SimplexField {
  CellVertices<D> ids{};
  double content = 0;
  double grad[max_cost_channels][D];
};

template <int D>
SimplexField<D> simplex_field(const std::vector<Vec<D>>& points, const float* values, int K,
                              const CellVertices<D>& ids, bool gradients) {
  SimplexField<D> f;
  f.ids = ids;
  std::array<Eigen::Matrix<double, D, 1>, D + 1> p;
  for (int i = 0; i <= D; ++i)
    for (int k = 0; k < D; ++k) p[i](k) = points[ids[i]][k];
  f.content = simplex_content<D>(p);
  if (!gradients) return f;
  for (int c = 0; c < K; ++c) {
    std::array<double, D + 1> z;
    for (int i = 0; i <= D; ++i) z[i] = values[static_cast<std::size_t>(ids[i]) * K + c];
    const Eigen::Matrix<double, D, 1> g = simplex_gradient<D>(p, z);
    for (int k = 0; k < D; ++k) f.grad[c][k] = g(k);
  }
  return f;
}

}  // namespace ddt::core
