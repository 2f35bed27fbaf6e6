// A mesh without triangles (collinear points): interpolation along the line.
#include "image/raster/scene.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace ddt::raster {

Image render_collinear(const Mesh2& mesh, const std::vector<float>& values, int C, const RenderGrid& grid, int row0,
                       int row1) {
  Image out(grid.width, row1 - row0, C);
  const auto& P = mesh.points;
  if (P.empty()) return out;
  // Direction through the two points farthest apart along the dominant axis.
  std::size_t first = 0, last = 0;
  const bool by_x = [&] {
    double sx = 0, sy = 0;
    for (const Point2& p : P) sx = std::max(sx, std::abs(p.x - P[0].x)), sy = std::max(sy, std::abs(p.y - P[0].y));
    return sx >= sy;
  }();
  for (std::size_t i = 1; i < P.size(); ++i) {
    const double key = by_x ? P[i].x : P[i].y;
    if (key < (by_x ? P[first].x : P[first].y)) first = i;
    if (key > (by_x ? P[last].x : P[last].y)) last = i;
  }
  const double dx = P[last].x - P[first].x, dy = P[last].y - P[first].y;
  const double len2 = dx * dx + dy * dy;
  std::vector<std::pair<double, index_t>> order;
  for (std::size_t i = 0; i < P.size(); ++i)
    order.emplace_back(len2 > 0 ? ((P[i].x - P[first].x) * dx + (P[i].y - P[first].y) * dy) / len2 : 0.0,
                       static_cast<index_t>(i));
  std::sort(order.begin(), order.end());
  tbb::parallel_for(row0, row1, [&](int Y) {
    for (int X = 0; X < grid.width; ++X) {
      const double x = grid.origin_x + (X + 0.5) / grid.scale_x, y = grid.origin_y + (Y + 0.5) / grid.scale_y;
      const double t = len2 > 0 ? ((x - P[first].x) * dx + (y - P[first].y) * dy) / len2 : 0.0;
      auto hi = std::lower_bound(order.begin(), order.end(), std::make_pair(t, index_t(-1)));
      float* px = &out.pixels[out.index(X, Y - row0)];
      if (hi == order.begin() || hi == order.end()) {
        const index_t v = (hi == order.end() ? order.back() : order.front()).second;
        for (int c = 0; c < C; ++c) px[c] = values[static_cast<std::size_t>(v) * C + c];
        continue;
      }
      auto lo = hi - 1;
      const double span = hi->first - lo->first;
      const double w = span > 0 ? (t - lo->first) / span : 0.0;
      for (int c = 0; c < C; ++c)
        px[c] = static_cast<float>((1 - w) * values[static_cast<std::size_t>(lo->second) * C + c] +
                                   w * values[static_cast<std::size_t>(hi->second) * C + c]);
    }
  });
  return out;
}

}  // namespace ddt::raster
