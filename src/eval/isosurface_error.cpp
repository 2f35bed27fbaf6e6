#include "eval/isosurface_error.hpp"

#include "eval/volume_pictures.hpp"

#include "util/error.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

namespace ddt {
namespace {

struct Line {
  std::array<int, 4> start;  // x, y, z, t of the first sample
  int axis;                  // 0, 1 or 2
};

// The angle between the picture's shading normal of step l at unit-cube
// point q and the true normal there, in degrees.
double normal_angle(const Volume& v, int l, const std::array<double, 3>& q, double t, const SurfaceDistance& distance) {
  const std::array<int, 4> n = v.size();
  // Outward: where values fall, against the picture's gradient.
  std::array<double, 3> g = shading_gradient(v, {q[0] * n[0], q[1] * n[1], q[2] * n[2]}, l), d{};
  for (double& x : g) x = -x;
  const double h = 1e-4;
  for (int c = 0; c < 3; ++c) {
    std::array<double, 3> a = q, b = q;
    a[c] += h, b[c] -= h;
    d[c] = distance(a[0], a[1], a[2], t) - distance(b[0], b[1], b[2], t);
  }
  const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  const double dn = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(gn > 0) || !(dn > 0)) return 90;
  const double cosine = std::clamp((g[0] * d[0] + g[1] * d[1] + g[2] * d[2]) / (gn * dn), -1.0, 1.0);
  return std::acos(cosine) * (180 / 3.14159265358979323846);
}

// RMS and 99th percentile of `values`, which it sorts.
std::pair<double, double> rms_p99(std::vector<double>& values) {
  double squares = 0;
  for (double x : values) squares += x * x;
  std::sort(values.begin(), values.end());
  const std::size_t at = std::min(values.size() - 1, static_cast<std::size_t>(0.99 * values.size()));
  return {std::sqrt(squares / values.size()), values[at]};
}

}  // namespace

IsosurfaceError isosurface_error(const Volume& v, double level, const SurfaceDistance& distance,
                                 const std::function<bool(int step)>& score_step) {
  if (v.empty()) throw Error("isosurface error: empty volume");
  if (!distance) throw Error("isosurface error: the field has no known surface");
  const std::array<int, 4> n = v.size();
  auto position = [&](int axis, double i) { return (i + 0.5) / n[axis]; };
  auto instant = [&](int l) { return n[3] > 1 ? double(l) / (n[3] - 1) : 0.0; };
  const double voxel = 1.0 / n[0];

  std::vector<int> steps;
  for (int l = 0; l < n[3]; ++l)
    if (!score_step || score_step(l)) steps.push_back(l);

  // One task per scored step and slice; each keeps its own distances.
  const int tasks = static_cast<int>(steps.size()) * n[2];
  std::vector<std::vector<double>> found(tasks), angles(tasks);
  std::vector<long long> truth(tasks, 0);
  tbb::parallel_for(0, tasks, [&](int task) {
    const int l = steps[task / n[2]], z = task % n[2];
    const double t = instant(l);
    std::vector<Line> lines;
    for (int y = 0; y < n[1]; ++y) lines.push_back({{0, y, z, l}, 0});
    for (int x = 0; x < n[0]; ++x) lines.push_back({{x, 0, z, l}, 1});
    if (z == 0)  // the z lines once per step
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x) lines.push_back({{x, y, 0, l}, 2});
    for (const Line& line : lines) {
      std::array<int, 4> at = line.start;
      auto value = [&] { return double(v.at4(at[0], at[1], at[2], at[3])); };
      auto signed_distance = [&](const std::array<double, 3>& p) { return distance(p[0], p[1], p[2], t); };
      std::array<double, 3> p{position(0, at[0]), position(1, at[1]), position(2, at[2])};
      double previous = value(), previous_true = signed_distance(p);
      for (int i = 1; i < n[line.axis]; ++i) {
        at[line.axis] = i;
        p[line.axis] = position(line.axis, i);
        const double current = value(), current_true = signed_distance(p);
        if ((previous_true < 0) != (current_true < 0)) ++truth[task];
        if ((previous < level) != (current < level)) {
          const double f = (level - previous) / (current - previous);
          std::array<double, 3> q = p;
          q[line.axis] = position(line.axis, i - 1 + f);
          found[task].push_back(std::abs(signed_distance(q)) / voxel);
          angles[task].push_back(normal_angle(v, l, q, t, distance));
        }
        previous = current, previous_true = current_true;
      }
    }
  });

  IsosurfaceError e;
  std::vector<double> all, all_angles;
  for (int task = 0; task < tasks; ++task) {
    all.insert(all.end(), found[task].begin(), found[task].end());
    all_angles.insert(all_angles.end(), angles[task].begin(), angles[task].end());
    e.true_crossings += truth[task];
  }
  e.crossings = static_cast<long long>(all.size());
  if (all.empty()) return e;
  double sum = 0;
  for (double d : all) sum += d;
  e.mean = sum / all.size();
  std::tie(e.rms, e.p99) = rms_p99(all);
  e.max = all.back();
  std::tie(e.normal_rms, e.normal_p99) = rms_p99(all_angles);
  return e;
}

}  // namespace ddt
