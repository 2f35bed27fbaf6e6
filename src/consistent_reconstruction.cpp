#include "consistent_reconstruction.hpp"

#include "error.hpp"
#include "footprint_operator.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>

namespace ddt {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

constexpr int max_channels = 16;
using PerChannel = std::array<double, max_channels>;

PerChannel dot(const std::vector<double>& a, const std::vector<double>& b, int C) {
  PerChannel d{};
  for (std::size_t i = 0; i < a.size(); ++i) d[i % C] += a[i] * b[i];
  return d;
}

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

// Solves A x = b for C interleaved right-hand sides at once: BiCGSTAB with
// the Jacobi preconditioner, each channel with its own scalars (van der
// Vorst 1992, the preconditioned form). Stops when max |b - A x| <= tol.
int bicgstab(const SparseRows& A, const std::vector<double>& b, std::vector<double>& x, int C, int max_iterations,
             double tol, double* final_residual) {
  const std::size_t n = b.size();
  std::vector<double> inv_diag(A.rows, 1.0);
  for (int i = 0; i < A.rows; ++i)
    for (std::int64_t k = A.start[i]; k < A.start[i + 1]; ++k)
      if (A.col[k] == i && std::abs(A.weight[k]) > 1e-3) inv_diag[i] = 1.0 / A.weight[k];
  auto precondition = [&](const std::vector<double>& in, std::vector<double>& out) {
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = inv_diag[i / C] * in[i];
  };
  x.assign(n, 0.0);
  std::vector<double> r = b, r0 = b, p(n, 0.0), v(n, 0.0), s(n), t(n), ph, sh;
  PerChannel rho{}, alpha{}, omega{};
  rho.fill(1);
  alpha.fill(1);
  omega.fill(1);
  double residual = max_abs(r);
  int it = 0;
  for (; it < max_iterations && residual > tol; ++it) {
    const PerChannel rho_new = dot(r0, r, C);
    for (std::size_t i = 0; i < n; ++i) {
      const int c = static_cast<int>(i % C);
      const double beta = rho[c] != 0 && omega[c] != 0 ? (rho_new[c] / rho[c]) * (alpha[c] / omega[c]) : 0;
      p[i] = r[i] + beta * (p[i] - omega[c] * v[i]);
    }
    rho = rho_new;
    precondition(p, ph);
    A.multiply(ph, v, C);
    const PerChannel r0v = dot(r0, v, C);
    for (int c = 0; c < C; ++c) alpha[c] = r0v[c] != 0 ? rho[c] / r0v[c] : 0;
    for (std::size_t i = 0; i < n; ++i) s[i] = r[i] - alpha[i % C] * v[i];
    precondition(s, sh);
    A.multiply(sh, t, C);
    const PerChannel ts = dot(t, s, C), tt = dot(t, t, C);
    for (int c = 0; c < C; ++c) omega[c] = tt[c] != 0 ? ts[c] / tt[c] : 0;
    for (std::size_t i = 0; i < n; ++i) {
      const int c = static_cast<int>(i % C);
      x[i] += alpha[c] * ph[i] + omega[c] * sh[i];
      r[i] = s[i] - omega[c] * t[i];
    }
    residual = max_abs(r);
  }
  // The true residual (the recursive one drifts).
  std::vector<double> ax;
  A.multiply(x, ax, C);
  double true_residual = 0;
  for (std::size_t i = 0; i < n; ++i) true_residual = std::max(true_residual, std::abs(b[i] - ax[i]));
  *final_residual = true_residual;
  return it;
}

// The range an output pixel may take in footprint (x, y) of channel c: that
// of the 3x3 input pixels around it. Where the pixel is the strict minimum
// of them it may hold a dark feature thinner than a pixel, whose truth is
// darker than any input pixel: the range reaches down to the 5x5
// minimum, and is open below where the pixel is the strict minimum of the
// 5x5 too (an isolated dark dot), down to the darkest input pixel of the
// image (no feature is darker than what the image shows somewhere whole);
// likewise above. A bright rim beside a
// dark line, or a dark one beside a bright line, lies outside it: that is
// the halo; and a bright gap between two dark strokes gets no brighter
// than the background seen within two pixels.
std::pair<float, float> halo_bounds(const Image& src, int x, int y, int c, float image_min, float image_max) {
  const float centre = src.at(x, y, c);
  float lo3 = centre, hi3 = centre, lo5 = centre, hi5 = centre;
  bool strict_min3 = true, strict_max3 = true, strict_min5 = true, strict_max5 = true;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int nx = std::clamp(x + dx, 0, src.width - 1), ny = std::clamp(y + dy, 0, src.height - 1);
      if (nx == x && ny == y) continue;
      const float v = src.at(nx, ny, c);
      const bool inner = std::abs(dx) <= 1 && std::abs(dy) <= 1;
      if (inner) {
        lo3 = std::min(lo3, v);
        hi3 = std::max(hi3, v);
        strict_min3 = strict_min3 && v > centre;
        strict_max3 = strict_max3 && v < centre;
      }
      lo5 = std::min(lo5, v);
      hi5 = std::max(hi5, v);
      strict_min5 = strict_min5 && v > centre;
      strict_max5 = strict_max5 && v < centre;
    }
  const float lo = !strict_min3 ? lo3 : strict_min5 ? image_min : lo5;
  const float hi = !strict_max3 ? hi3 : strict_max5 ? image_max : hi5;
  return {lo, hi};
}

// Removes halos without losing consistency: in each footprint (the output
// pixels whose centres lie in input pixel (x, y)), values are clamped to
// halo_bounds after a common shift t, the one that keeps the footprint's
// mean (the mean of clamp(o + t) grows with t). At
// integer scales a footprint's mean is exactly what the box model
// acquires, so consistency is kept exactly; elsewhere nearly.
long long limit_halos(Image& out, const Image& src) {
  const double sx = static_cast<double>(out.width) / src.width, sy = static_cast<double>(out.height) / src.height;
  std::vector<int> first_x(src.width + 1), first_y(src.height + 1);
  for (int x = 0; x <= src.width; ++x) first_x[x] = std::min(out.width, static_cast<int>(std::ceil(x * sx - 0.5)));
  for (int y = 0; y <= src.height; ++y) first_y[y] = std::min(out.height, static_cast<int>(std::ceil(y * sy - 0.5)));
  std::vector<float> image_min(src.channels, INFINITY), image_max(src.channels, -INFINITY);
  for (std::size_t i = 0; i < src.pixels.size(); ++i) {
    image_min[i % src.channels] = std::min(image_min[i % src.channels], src.pixels[i]);
    image_max[i % src.channels] = std::max(image_max[i % src.channels], src.pixels[i]);
  }
  std::atomic<long long> limited{0};
  tbb::parallel_for(0, src.height, [&](int y) {
    std::vector<float> o;
    for (int x = 0; x < src.width; ++x)
      for (int c = 0; c < src.channels; ++c) {
        const auto [lo, hi] = halo_bounds(src, x, y, c, image_min[c], image_max[c]);
        o.clear();
        float omin = INFINITY, omax = -INFINITY;
        for (int Y = first_y[y]; Y < first_y[y + 1]; ++Y)
          for (int X = first_x[x]; X < first_x[x + 1]; ++X) {
            o.push_back(out.at(X, Y, c));
            omin = std::min(omin, o.back());
            omax = std::max(omax, o.back());
          }
        if (o.empty() || (omin >= lo && omax <= hi)) continue;
        double mean = 0;
        for (float v : o) mean += v;
        mean /= o.size();
        // The mean is the input pixel, inside [lo, hi] up to the solver's
        // tolerance; a mean on a bound leaves one answer, the flat bound.
        if (!(mean >= lo - 1e-5 && mean <= hi + 1e-5)) continue;  // cannot hold: keep the consistent values
        mean = std::clamp(mean, double(lo), double(hi));
        // mean(clamp(o + t)) is piecewise linear and increasing in t:
        // Newton steps on its slope (the share of unclamped values),
        // safeguarded by a bracket.
        double a = std::isfinite(lo) ? lo - omax : -(omax - omin) - 1, b = std::isfinite(hi) ? hi - omin : (omax - omin) + 1;
        double t = 0;
        for (int it = 0; it < 60; ++it) {
          double m = 0;
          int free = 0;
          for (float v : o) {
            const double x = v + t;
            if (x <= lo) m += lo;
            else if (x >= hi) m += hi;
            else m += x, ++free;
          }
          const double gap = mean - m / o.size();
          if (std::abs(gap) < 1e-9) break;
          (gap > 0 ? a : b) = t;
          const double next = free > 0 ? t + gap * o.size() / free : 0.5 * (a + b);
          t = next > a && next < b ? next : 0.5 * (a + b);
        }
        for (int Y = first_y[y]; Y < first_y[y + 1]; ++Y)
          for (int X = first_x[x]; X < first_x[x + 1]; ++X) {
            float& v = out.at(X, Y, c);
            v = static_cast<float>(std::clamp(v + t, double(lo), double(hi)));
          }
        ++limited;
      }
  });
  return limited;
}

}  // namespace

void make_consistent(Image& out, const Mesh2& mesh, const Mesh2& grid_mesh, const Image& src,
                     const ConsistencyOptions& options, ConsistencyStats* stats) {
  if (options.model.kind == AcquisitionModel::Kind::point) return;
  const int W = src.width, H = src.height, C = src.channels;
  if (C > max_channels) throw Error("the consistent reconstruction takes at most 16 channels");
  ConsistencyStats local;

  auto t0 = std::chrono::steady_clock::now();
  const std::vector<index_t> owners = pixel_owners(mesh, W, H, out.width, out.height);
  const std::vector<index_t> grid_owners = pixel_owners(grid_mesh, W, H, out.width, out.height);
  const SparseRows A = footprint_operator(mesh, owners, W, H, out.width, out.height, options.model);
  const SparseRows G = footprint_operator(grid_mesh, grid_owners, W, H, out.width, out.height, options.model);
  local.nonzeros = static_cast<long long>(A.col.size());
  local.seconds_operator = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const std::vector<double> residual = residual_of(options.model, out, src);
  local.residual_before = max_abs(residual);
  std::vector<double> delta_mesh, delta_grid;
  const std::vector<double> rest =
      back_project(A, residual, delta_mesh, C, options.mesh_steps, 0.01, &local.mesh_steps);
  local.residual_mesh = max_abs(rest);
  local.iterations =
      bicgstab(G, rest, delta_grid, C, options.max_iterations, options.tolerance, &local.residual_after);
  local.seconds_solve = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  add_linear_surface(out, mesh, owners, W, H, delta_mesh);
  add_linear_surface(out, grid_mesh, grid_owners, W, H, delta_grid);
  if (options.limit_halos) {
    local.halo_footprints = limit_halos(out, src);
    // Where limiting moved a footprint's acquisition (models other than
    // box, non-integer scales), one more exact correction on the grid; box
    // at integer scales acquires exactly the footprint means it kept.
    const bool kept_exactly = options.model.kind == AcquisitionModel::Kind::box && out.width % W == 0 &&
                              out.height % H == 0;
    if (kept_exactly || local.halo_footprints == 0) {
      local.seconds_render = seconds_since(t0);
      if (stats) *stats = local;
      return;
    }
    const std::vector<double> rest_after = residual_of(options.model, out, src);
    if (max_abs(rest_after) > 10 * options.tolerance) {
      std::vector<double> delta;
      double residual = 0;
      local.iterations += bicgstab(G, rest_after, delta, C, options.max_iterations, options.tolerance, &residual);
      add_linear_surface(out, grid_mesh, grid_owners, W, H, delta);
      ++local.halo_passes;
    }
  }
  local.seconds_render = seconds_since(t0);
  if (stats) *stats = local;
}

}  // namespace ddt
