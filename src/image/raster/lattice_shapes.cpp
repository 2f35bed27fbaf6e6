#include "image/raster/lattice_shapes.hpp"

#include <algorithm>

namespace ddt::raster {

// d1 = p1 - p0, d2 = p2 - p0 (whole pixels), phase = p0 - floor(p0); the
// image has row_floats floats a row, C a pixel. The pixel list only when
// the shape has at most list_limit pixels.
Shape build_shape(const int d1[2], const int d2[2], const Point2& phase, std::ptrdiff_t row_floats, int C, bool cubic,
                  long long list_limit) {
  // Local coordinates, all at least 1 (first_right clamps below 0).
  const int ox = 1 - std::min({0, d1[0], d2[0]}), oy = 1 - std::min({0, d1[1], d2[1]});
  const Point2 q[3] = {{phase.x + ox, phase.y + oy},
                       {phase.x + ox + d1[0], phase.y + oy + d1[1]},
                       {phase.x + ox + d2[0], phase.y + oy + d2[1]}};
  const double y_min = std::min({q[0].y, q[1].y, q[2].y}), y_max = std::max({q[0].y, q[1].y, q[2].y});
  constexpr int unbounded = 1 << 30;
  Shape shape;
  bool first = true;
  // Rows y_min <= Y < y_max, as the walk crosses them: one downward edge
  // (its left side is the triangle) and one upward edge (reversed: its
  // right side is).
  for (int Y = ceil_int(y_min); Y < y_max; ++Y) {
    int left = 0, right = 0;
    for (int k = 0; k < 3; ++k) {
      const Point2 &u = q[k], &v = q[(k + 1) % 3];
      if (u.y <= Y && Y < v.y) Crossing(u, v, true).first_right(Y, 1, unbounded, &right);
      if (v.y <= Y && Y < u.y) Crossing(v, u, true).first_right(Y, 1, unbounded, &left);
    }
    const int row = Y - oy, xs = left - ox, xe = std::max(right, left) - ox;
    shape.rows.push_back({row, xs, xe});  // empty rows too: pieces are runs of rows
    if (xe == xs) continue;
    shape.pixel_count += xe - xs;
    if (first) shape.min_ox = xs, shape.max_ox = xe - 1, shape.min_oy = row, first = false;
    shape.min_ox = std::min(shape.min_ox, xs), shape.max_ox = std::max(shape.max_ox, xe - 1), shape.max_oy = row;
  }
  if (shape.pixel_count == 0 || shape.pixel_count > list_limit) return shape;
  const double inv_area2 = 1.0 / signed_area2(q[0], q[1], q[2]);
  for (const auto& [row, xs, xe] : shape.rows) {
    shape.row_first.push_back(shape.placed.size());
    for (int x = xs; x < xe; ++x) {
      shape.placed.push_back({row - phase.y, xs - phase.x, double(x - xs), row * row_floats + std::ptrdiff_t(x) * C});
      if (cubic) {
        // Edge functions of q_k -> q_(k+1) at the pixel centre, as draw_bernstein().
        const double X = x + ox, Y = row + oy;
        double e[3];
        for (int k = 0; k < 3; ++k) {
          const Point2 &u = q[k], &v = q[(k + 1) % 3];
          e[k] = (v.x - u.x) * (Y - u.y) - (v.y - u.y) * (X - u.x);
        }
        bernstein_monomials(e[1] * inv_area2, e[2] * inv_area2, e[0] * inv_area2, shape.monomials.emplace_back().data());
      }
    }
  }
  shape.row_first.push_back(shape.placed.size());
  return shape;
}

const Shape* ShapeTable::find(const int d1[2], const int d2[2], const Point2& phase) {
  for (int v : {d1[0], d1[1], d2[0], d2[1]})
    if (std::abs(v) > max_offset) return nullptr;
  const std::uint64_t key = shape_key(d1, d2);
  if (key == 0) return nullptr;  // no triangle; key 0 marks empty slots
  std::size_t h = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> (64 - capacity_bits));
  for (;; h = (h + 1) & (capacity - 1)) {
    const std::uint64_t k = slots_[h].key.load(std::memory_order_acquire);
    if (k == key) return slots_[h].shape.load(std::memory_order_acquire);
    if (k == 0) break;
  }
  const std::lock_guard<std::mutex> lock(mutex_);
  for (;; h = (h + 1) & (capacity - 1)) {
    const std::uint64_t k = slots_[h].key.load(std::memory_order_acquire);
    if (k == key) return slots_[h].shape.load(std::memory_order_acquire);
    if (k == 0) break;
  }
  if (4 * (shapes_.size() + 1) > 3 * capacity) return nullptr;
  shapes_.push_back(build_shape(d1, d2, phase, row_floats_, C_, cubic_,
                                std::min(max_listed_pixels, listed_budget - listed_)));
  listed_ += static_cast<long long>(shapes_.back().placed.size());
  slots_[h].shape.store(&shapes_.back(), std::memory_order_release);
  slots_[h].key.store(key, std::memory_order_release);
  return &shapes_.back();
}

bool shapes_repeat(const SceneGeometry& scene) {
  const index_t n = std::min<index_t>(scene.T, 4096), step = scene.T / n;
  std::vector<std::uint64_t> keys;
  keys.reserve(n);
  for (index_t i = 0; i < n; ++i) {
    index_t id[3];
    scene.corners(i * step, id);
    const Point2 p[3] = {scene.pos(id[0]), scene.pos(id[1]), scene.pos(id[2])};
    int d1[2], d2[2];
    shape_offsets(p, d1, d2);
    keys.push_back(shape_key(d1, d2));
  }
  std::sort(keys.begin(), keys.end());
  const auto distinct = std::unique(keys.begin(), keys.end()) - keys.begin();
  return 4 * distinct <= n;
}

}  // namespace ddt::raster
