#include "consistency/consistent_reconstruction.hpp"

#include "util/error.hpp"
#include "consistency/footprint_operator.hpp"
#include "consistency/grid_surface.hpp"
#include "consistency/halo_limit.hpp"
#include "consistency/step_edges.hpp"
#include "util/timing.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ddt {
namespace {

constexpr int max_channels = 16;

double max_abs(const std::vector<double>& a) {
  double m = 0;
  for (double v : a) m = std::max(m, std::abs(v));
  return m;
}

// src - acquire(out): what the output still fails to reproduce.
std::vector<double> residual_of(const AcquisitionModel& model, const Image& out, const Image& src) {
  const Image predicted = apply_acquisition(model, out, src.width, src.height);
  std::vector<double> r(src.pixels.size());
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = double(src.pixels[i]) - predicted.pixels[i];
  return r;
}

double norm2(const std::vector<double>& a) {
  double m = 0;
  for (double v : a) m += v * v;
  return m;
}

// Back-projection x += b - A x from x = 0 while the residual's 2-norm falls
// by at least `min_gain` per step, at most `steps` steps. Returns b - A x.
std::vector<double> back_project(const SparseRows& A, const std::vector<double>& b, std::vector<double>& x, int C,
                                 int steps, double min_gain, int* done) {
  x.assign(b.size(), 0.0);
  std::vector<double> r = b, ax, best_x = x, best_r = r;
  double best = norm2(r);
  *done = 0;
  for (int k = 0; k < steps; ++k) {
    for (std::size_t i = 0; i < x.size(); ++i) x[i] += r[i];
    A.multiply(x, ax, C);
    for (std::size_t i = 0; i < x.size(); ++i) r[i] = b[i] - ax[i];
    const double now = norm2(r);
    if (!(now < best * (1 - min_gain))) break;
    best = now;
    best_x = x;
    best_r = r;
    *done = k + 1;
  }
  x = best_x;
  return best_r;
}

}  // namespace

void make_consistent(Image& out, const Mesh2& mesh, const Image& src, const ConsistencyOptions& options,
                     ConsistencyStats* stats) {
  if (options.model.kind == AcquisitionModel::Kind::point) return;
  const int W = src.width, H = src.height, C = src.channels;
  if (C > max_channels) throw Error("the consistent reconstruction takes at most 16 channels");
  ConsistencyStats local;

  auto t0 = std::chrono::steady_clock::now();
  const std::vector<index_t> owners = pixel_owners(mesh, W, H, out.width, out.height);
  const SparseRows A = footprint_operator(mesh, owners, W, H, out.width, out.height, options.model);
  const GridSurface grid(W, H, out.width, out.height, options.model);
  local.nonzeros = static_cast<long long>(A.col.size());
  local.seconds_operator = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const std::vector<double> residual = residual_of(options.model, out, src);
  local.residual_before = max_abs(residual);
  std::vector<double> delta_mesh, delta_grid;
  const std::vector<double> rest =
      back_project(A, residual, delta_mesh, C, options.mesh_steps, 0.01, &local.mesh_steps);
  local.residual_mesh = max_abs(rest);
  grid.solve(rest, delta_grid, C);
  {
    std::vector<double> acquired;
    grid.acquire(delta_grid, acquired, C);
    for (std::size_t i = 0; i < acquired.size(); ++i)
      local.residual_after = std::max(local.residual_after, std::abs(rest[i] - acquired[i]));
  }
  local.seconds_solve = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  add_linear_surface(out, mesh, owners, W, H, delta_mesh);
  grid.add_to(out, delta_grid);
  // Under the box model a footprint crossed by one straight edge shows
  // where the edge passes inside it: drawn as that edge (step_edges.hpp).
  if (options.step_edges && options.model.kind == AcquisitionModel::Kind::box)
    local.step_edge_footprints = render_step_edges(out, src);
  if (options.limit_halos) local.halo_footprints = limit_halos(out, src);
  // Where these moved a footprint's acquisition (models other than box,
  // non-integer scales), one more exact correction on the grid; box at
  // integer scales acquires exactly the footprint means they kept.
  const bool kept_exactly =
      options.model.kind == AcquisitionModel::Kind::box && out.width % W == 0 && out.height % H == 0;
  if (!kept_exactly && local.halo_footprints + local.step_edge_footprints > 0) {
    const std::vector<double> rest_after = residual_of(options.model, out, src);
    if (max_abs(rest_after) > 10 * options.tolerance) {
      std::vector<double> delta;
      grid.solve(rest_after, delta, C);
      grid.add_to(out, delta);
      ++local.halo_passes;
    }
  }
  local.seconds_render = seconds_since(t0);
  if (stats) *stats = local;
}

}  // namespace ddt
