#include "eval/volume_pictures.hpp"

#include "util/error.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace ddt {

double trilinear_at(const Volume& v, const std::array<double, 3>& u, int step) {
  const int n[3] = {v.nx, v.ny, v.nz};
  int i0[3], i1[3];
  double w[3];
  for (int a = 0; a < 3; ++a) {
    const double p = std::clamp(u[a] - 0.5, 0.0, n[a] - 1.0);
    i0[a] = std::min(static_cast<int>(p), n[a] - 1);
    i1[a] = std::min(i0[a] + 1, n[a] - 1);
    w[a] = p - i0[a];
  }
  auto at = [&](int a, int b, int c) {
    return double(v.at4(a ? i1[0] : i0[0], b ? i1[1] : i0[1], c ? i1[2] : i0[2], step));
  };
  double sum = 0;
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a)
        sum += (a ? w[0] : 1 - w[0]) * (b ? w[1] : 1 - w[1]) * (c ? w[2] : 1 - w[2]) * at(a, b, c);
  return sum;
}

std::array<double, 3> shading_gradient(const Volume& v, const std::array<double, 3>& p, int step) {
  const double h = 0.5;
  std::array<double, 3> g{};
  for (int c = 0; c < 3; ++c) {
    std::array<double, 3> q1 = p, q2 = p;
    q1[c] += h, q2[c] -= h;
    g[c] = trilinear_at(v, q1, step) - trilinear_at(v, q2, step);
  }
  return g;
}

Image isosurface_view(const Volume& v, const IsoView& view, int size) {
  if (v.empty() || size < 1) throw Error("isosurface_view: empty volume or picture");
  const double az = view.azimuth * M_PI / 180, el = view.elevation * M_PI / 180;
  // d: from the eye into the scene; right and up span the picture.
  const double d[3] = {-std::cos(el) * std::cos(az), -std::cos(el) * std::sin(az), -std::sin(el)};
  double right[3] = {-d[1], d[0], 0};
  const double rn = std::hypot(right[0], right[1]);
  if (rn < 1e-12) right[0] = 1, right[1] = 0;
  else right[0] /= rn, right[1] /= rn;
  const double up[3] = {right[1] * d[2] - right[2] * d[1], right[2] * d[0] - right[0] * d[2],
                        right[0] * d[1] - right[1] * d[0]};
  const double centre[3] = {v.nx / 2.0, v.ny / 2.0, v.nz / 2.0};
  const double radius = 0.5 * std::sqrt(double(v.nx) * v.nx + double(v.ny) * v.ny + double(v.nz) * v.nz);
  const double half_side = radius / std::max(view.zoom, 1e-6);
  const double hi[3] = {double(v.nx), double(v.ny), double(v.nz)};
  Image out(size, size, 1, 0.0f);
  tbb::parallel_for(0, size, [&](int row) {
    for (int col = 0; col < size; ++col) {
      const double sx = ((col + 0.5) / size * 2 - 1) * half_side, sy = (1 - (row + 0.5) / size * 2) * half_side;
      double o[3];
      for (int a = 0; a < 3; ++a) o[a] = centre[a] + sx * right[a] + sy * up[a] - 2 * radius * d[a];
      // Clip the ray to the volume's box.
      double t0 = 0, t1 = 4 * radius;
      for (int a = 0; a < 3 && t0 <= t1; ++a) {
        if (std::abs(d[a]) < 1e-12) {
          if (o[a] < 0 || o[a] > hi[a]) t0 = t1 + 1;
          continue;
        }
        double ta = (0 - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (t0 > t1) continue;
      auto f = [&](double t) { return trilinear_at(v, {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]}) - view.level; };
      double prev_t = t0, prev = f(t0);
      if (prev >= 0) {  // starts inside: draw the box face, flat
        out.at(col, row) = 0.35f;
        continue;
      }
      for (double t = t0 + view.step; t <= t1 + view.step; t += view.step) {
        const double tc = std::min(t, t1), cur = f(tc);
        if (cur >= 0) {
          double a = prev_t, b = tc;
          for (int k = 0; k < 20; ++k) {
            const double m = 0.5 * (a + b);
            (f(m) >= 0 ? b : a) = m;
          }
          const std::array<double, 3> g = shading_gradient(v, {o[0] + b * d[0], o[1] + b * d[1], o[2] + b * d[2]});
          const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
          // The outward normal is -g (values rise inward); the light comes from the eye.
          const double lambert = gn > 0 ? std::max(0.0, (g[0] * d[0] + g[1] * d[1] + g[2] * d[2]) / gn) : 1.0;
          out.at(col, row) = static_cast<float>(0.12 + 0.88 * lambert);
          break;
        }
        prev_t = tc;
        prev = cur;
        if (tc >= t1) break;
      }
    }
  });
  return out;
}

Image volume_view(const Volume& v, VolumeView view, const IsoView& iso) {
  switch (view) {
    case VolumeView::isosurface: return isosurface_view(v, iso, iso.size > 0 ? iso.size : std::max({v.nx, v.ny, v.nz}));
    case VolumeView::slice_xy: {
      Image img(v.nx, v.ny, 1);
      for (int y = 0; y < v.ny; ++y)
        for (int x = 0; x < v.nx; ++x) img.at(x, y) = v.at(x, y, v.nz / 2);
      return img;
    }
    case VolumeView::slice_xz: {
      Image img(v.nx, v.nz, 1);
      for (int z = 0; z < v.nz; ++z)
        for (int x = 0; x < v.nx; ++x) img.at(x, z) = v.at(x, v.ny / 2, z);
      return img;
    }
    case VolumeView::slice_yz: {
      Image img(v.ny, v.nz, 1);
      for (int z = 0; z < v.nz; ++z)
        for (int y = 0; y < v.ny; ++y) img.at(y, z) = v.at(v.nx / 2, y, z);
      return img;
    }
    case VolumeView::mip_z: {
      Image img(v.nx, v.ny, 1, -HUGE_VALF);
      for (int z = 0; z < v.nz; ++z)
        for (int y = 0; y < v.ny; ++y)
          for (int x = 0; x < v.nx; ++x) img.at(x, y) = std::max(img.at(x, y), v.at(x, y, z));
      return img;
    }
  }
  return {};
}

void value_range(const Volume& v, double& lo, double& hi) {
  if (v.empty()) throw Error("value_range: the volume is empty");
  const auto [mn, mx] = std::minmax_element(v.voxels.begin(), v.voxels.end());
  lo = *mn;
  hi = *mx;
}

Image compare_views(const std::vector<const Volume*>& volumes, const std::vector<VolumeView>& views, double lo,
                    double hi, const IsoView& iso) {
  if (volumes.empty() || views.empty()) throw Error("compare_views: nothing to show");
  for (const Volume* v : volumes)
    if (v->nx != volumes[0]->nx || v->ny != volumes[0]->ny || v->nz != volumes[0]->nz)
      throw Error("compare_views: the volumes differ in size");
  constexpr int gap = 4;
  std::vector<int> row_height, row_top;
  int cell_width = 0, height = gap;
  for (VolumeView view : views) {
    const int iso_side = iso.size > 0 ? iso.size : std::max({volumes[0]->nx, volumes[0]->ny, volumes[0]->nz});
    const Image probe = view == VolumeView::isosurface ? Image(iso_side, iso_side, 1) : volume_view(*volumes[0], view);
    cell_width = std::max(cell_width, probe.width);
    row_top.push_back(height);
    row_height.push_back(probe.height);
    height += probe.height + gap;
  }
  const int columns = static_cast<int>(volumes.size());
  Image out(gap + columns * (cell_width + gap), height, 1, 0.1f);
  const double span = hi > lo ? hi - lo : 1.0;
  for (int c = 0; c < columns; ++c)
    for (std::size_t r = 0; r < views.size(); ++r) {
      const Image cell = volume_view(*volumes[c], views[r], iso);
      const bool shaded = views[r] == VolumeView::isosurface;
      const int left = gap + c * (cell_width + gap);
      for (int y = 0; y < cell.height; ++y)
        for (int x = 0; x < cell.width; ++x)
          out.at(left + x, row_top[r] + y) =
              shaded ? cell.at(x, y) : static_cast<float>(std::clamp((cell.at(x, y) - lo) / span, 0.0, 1.0));
    }
  return out;
}

Image series_xt_view(const Volume& v) {
  if (v.empty()) throw Error("series_xt_view: the volume is empty");
  Image img(v.nx, v.nt, 1);
  for (int t = 0; t < v.nt; ++t)
    for (int x = 0; x < v.nx; ++x) img.at(x, t) = v.at4(x, v.ny / 2, v.nz / 2, t, 0);
  return img;
}

Image compare_series_views(const std::vector<const Volume*>& series, int step, const std::vector<VolumeView>& views,
                           double lo, double hi, const IsoView& iso) {
  if (series.empty()) throw Error("compare_series_views: nothing to show");
  std::vector<Volume> steps, planes;
  for (const Volume* v : series) {
    if (v->size() != series[0]->size()) throw Error("compare_series_views: the series differ in size");
    if (step < 0 || step >= v->nt) throw Error("compare_series_views: no time step " + std::to_string(step));
    steps.push_back(time_step(*v, step));
    const Image xt = series_xt_view(*v);
    Volume plane(xt.width, xt.height, 1);  // the x-t plane as a one-slice volume: its x-y slice
    std::copy(xt.pixels.begin(), xt.pixels.end(), plane.voxels.begin());
    planes.push_back(std::move(plane));
  }
  std::vector<const Volume*> step_columns, plane_columns;
  for (std::size_t i = 0; i < series.size(); ++i) step_columns.push_back(&steps[i]), plane_columns.push_back(&planes[i]);
  const Image top = compare_views(step_columns, views, lo, hi, iso);
  const Image bottom = compare_views(plane_columns, {VolumeView::slice_xy}, lo, hi);
  // Stacked; the second picture's top gap is the first's bottom one.
  constexpr int gap = 4;
  Image out(std::max(top.width, bottom.width), top.height + bottom.height - gap, 1, 0.1f);
  for (int y = 0; y < top.height; ++y)
    for (int x = 0; x < top.width; ++x) out.at(x, y) = top.at(x, y);
  for (int y = gap; y < bottom.height; ++y)
    for (int x = 0; x < bottom.width; ++x) out.at(x, top.height - gap + y) = bottom.at(x, y);
  return out;
}

std::vector<const Volume*> picture_columns(const Volume& reference, const std::map<std::string, Volume>& results,
                                           const std::vector<std::string>& methods) {
  std::vector<const Volume*> columns = {&reference};
  for (const std::string& spec : methods) {
    const auto it = results.find(spec);
    if (it == results.end()) throw Error("picture method '" + spec + "' is not among the methods run");
    columns.push_back(&it->second);
  }
  return columns;
}

}  // namespace ddt
