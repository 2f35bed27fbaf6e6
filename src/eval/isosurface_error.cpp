#include "eval/isosurface_error.hpp"

#include "util/error.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace ddt {
namespace {

struct Line {
  std::array<int, 4> start;  // x, y, z, t of the first sample
  int axis;                  // 0, 1 or 2
};

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
  std::vector<std::vector<double>> found(tasks);
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
        }
        previous = current, previous_true = current_true;
      }
    }
  });

  IsosurfaceError e;
  std::vector<double> all;
  for (int task = 0; task < tasks; ++task) {
    all.insert(all.end(), found[task].begin(), found[task].end());
    e.true_crossings += truth[task];
  }
  e.crossings = static_cast<long long>(all.size());
  if (all.empty()) return e;
  double sum = 0, squares = 0;
  for (double d : all) sum += d, squares += d * d;
  e.mean = sum / all.size();
  e.rms = std::sqrt(squares / all.size());
  std::sort(all.begin(), all.end());
  e.max = all.back();
  e.p99 = all[std::min(all.size() - 1, static_cast<std::size_t>(0.99 * all.size()))];
  return e;
}

}  // namespace ddt
