#pragma once
// Draw by shape, the lattice fast path of the linear and cubic render
// (image/rasterizer.hpp): the same pixels and bits as the walk.

#include "image/raster/walk.hpp"

#include <atomic>
#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

namespace ddt::raster {

// Lattice meshes: every vertex at the same fractional position in output
// pixels (pixel centres at integer scales), so the triangles are copies of
// a few shapes moved by whole pixels, and with exact coordinates so are the
// pixels they own. A shape's pixels are found once, by the walk's own
// crossings (first_right, exact and shift-invariant), and each copy draws
// from the list: no walk, no crossings, and for the linear render no rows
// (a flat loop; small scales are bound by the work per triangle and row).
// Same pixels, same values bit for bit; the rim is still walked.
// Shapes pay where triangles own few pixels; at large scales the walk's
// order keeps the rows' cache lines and wins. The thresholds below (output
// pixels per input unit area) are where the two cross (docs/performance.md,
// "Lattice meshes drawn by shape").
constexpr double shape_max_scale2_linear = 100, shape_max_scale2_cubic = 36;

struct Shape {
  // Offsets from the pixel floor(p0): rows (oy, xs, xe), the pixels
  // [xs, xe) of row oy, every row the triangle crosses, top to bottom.
  std::vector<std::array<int, 3>> rows;
  long long pixel_count = 0;
  int min_ox = 0, max_ox = 0, min_oy = 0, max_oy = 0;  // bounds of the pixels
  // Kept shapes of few pixels also list them (else drawn by rows): each as
  // the linear render needs it, Y - p0.y and xs - p0.x (exact, so equal to
  // the walk's), x - xs, and its offset in the image's floats from pixel
  // floor(p0).
  struct Placed {
    double dy, dxs, dx;
    std::ptrdiff_t offset;
  };
  std::vector<Placed> placed;
  // Cubic, with the list: where each row's pixels start in `placed` (one
  // more entry than rows), and each pixel's Bernstein monomials as pixel()
  // computes them (from exact edge functions and 1 / area2: the walk's bits).
  std::vector<std::size_t> row_first;
  std::vector<std::array<double, 10>> monomials;
};

// d1 = p1 - p0, d2 = p2 - p0 (whole pixels), phase = p0 - floor(p0); the
// image has row_floats floats a row, C a pixel. The pixel list only when
// the shape has at most list_limit pixels.
Shape build_shape(const int d1[2], const int d2[2], const Point2& phase, std::ptrdiff_t row_floats, int C, bool cubic,
                  long long list_limit);

// A lattice triangle's offsets in whole output pixels: d1 = p1 - p0 and
// d2 = p2 - p0 (exact integers on a lattice).
inline void shape_offsets(const Point2 p[3], int d1[2], int d2[2]) {
  d1[0] = static_cast<int>(p[1].x - p[0].x), d1[1] = static_cast<int>(p[1].y - p[0].y);
  d2[0] = static_cast<int>(p[2].x - p[0].x), d2[1] = static_cast<int>(p[2].y - p[0].y);
}

// The offsets packed in 16 bits each (unique for offsets below 2^15).
inline std::uint64_t shape_key(const int d1[2], const int d2[2]) {
  std::uint64_t key = 0;
  for (int v : {d1[0], d1[1], d2[0], d2[1]}) key = key << 16 | static_cast<std::uint16_t>(v);
  return key;
}

// The shapes met so far, shared by the threads drawing: lookups without a
// lock (a slot's shape is published before its key), insertions under one.
class ShapeTable {
 public:
  ShapeTable(std::ptrdiff_t row_floats, int C, bool cubic)
      : slots_(capacity), row_floats_(row_floats), C_(C), cubic_(cubic) {}
  // The shape of (d1, d2), built on first use; nullptr for offsets over
  // max_offset or a full table (the caller draws such a triangle from
  // rows_of()).
  const Shape* find(const int d1[2], const int d2[2], const Point2& phase);
  std::size_t size() const { return shapes_.size(); }
  // A shape for one triangle: its rows only.
  Shape rows_of(const int d1[2], const int d2[2], const Point2& phase) const {
    return build_shape(d1, d2, phase, row_floats_, C_, cubic_, 0);
  }

 private:
  // Offsets up to 64 pixels; pixel lists for shapes of up to 4096 pixels,
  // 2^20 pixels in all (at most 112 MB with the cubic's monomials).
  static constexpr int capacity_bits = 14, max_offset = 64;
  static constexpr long long max_listed_pixels = 4096, listed_budget = 1 << 20;
  long long listed_ = 0;
  static constexpr std::size_t capacity = std::size_t(1) << capacity_bits;
  struct Slot {
    std::atomic<std::uint64_t> key{0};
    std::atomic<const Shape*> shape{nullptr};
  };
  std::vector<Slot> slots_;
  std::deque<Shape> shapes_;  // stable addresses
  std::mutex mutex_;
  std::ptrdiff_t row_floats_;
  int C_;
  bool cubic_;
};

// Shapes pay when they repeat: at most one distinct shape in four of a
// sample of the triangles (an image grid has about 100 shapes in all; a
// sparse subset of a lattice, each triangle its own, is walked instead:
// listing pixels once for one use costs more than drawing them).
bool shapes_repeat(const SceneGeometry& scene);

// Draws mesh triangle t of a lattice mesh from its shape: rows [row0, row1)
// of the grid, to out row - shift. Adds its pixels and pieces to counts.
template <int CT, bool cubic>
void draw_by_shape(const Scene& scene, index_t t, ShapeTable& table, const Point2& phase,
                   const std::vector<int>& group_of_row, int row0, int row1, int shift, Image& out, Shape& own,
                   std::vector<int>& left, std::vector<int>& right, DrawCounts& counts) {
  index_t id[3];
  Point2 p[3];
  scene.corners(t, id);
  for (int i = 0; i < 3; ++i) p[i] = scene.pos(id[i]);
  if (std::max({p[0].y, p[1].y, p[2].y}) < row0 || std::min({p[0].y, p[1].y, p[2].y}) >= row1) return;  // rows y_min <= Y < y_max
  const int bx = floor_int(p[0].x), by = floor_int(p[0].y);
  int d1[2], d2[2];
  shape_offsets(p, d1, d2);
  const Shape* shape = table.find(d1, d2, phase);
  if (!shape) own = table.rows_of(d1, d2, phase), shape = &own;
  if (shape->pixel_count == 0 || by + shape->max_oy < row0 || by + shape->min_oy >= row1) return;
  ++counts.shaped_triangles;
  const int W = out.width, C = out.channels;
  const bool clipped = bx + shape->min_ox < 0 || bx + shape->max_ox >= W || by + shape->min_oy < row0 ||
                       by + shape->max_oy >= row1;
  // Pixel floor(p0) in the image's floats; it may lie outside the image
  // (only the sums with the pixels' offsets are inside).
  const std::ptrdiff_t origin = (static_cast<std::ptrdiff_t>(by - shift) * W + bx) * C;
  float* const image = out.pixels.data();
  if constexpr (!cubic) {
    Shader<CT, false> shader;
    const double area2 = signed_area2(p[0], p[1], p[2]);
    shader.init(scene, t, id, p[0], p[1], p[2], area2, 0);
    if (!clipped && !shape->placed.empty()) {
      // One loop over the pixels, no loop per row: rows of 1 to 4 pixels
      // (small scales) cost a mispredicted exit each.
      for (const Shape::Placed& q : shape->placed) shader.placed_pixel(q.dy, q.dxs, q.dx, image + (origin + q.offset));
      counts.pixels += shape->pixel_count;
      return;
    }
    // Row by row as the walk draws them (a row's first pixel clamped to the image).
    for (const auto& [oy, xs, xe] : shape->rows) {
      const int y = by + oy, first = std::clamp(bx + xs, 0, W), end = std::clamp(bx + xe, 0, W);
      if (y < row0 || y >= row1 || end <= first) continue;
      shader.row(y, first, end - 1, &out.pixels[out.index(first, y - shift)]);
      counts.pixels += end - first;
    }
  } else {
    // Pieces as the walk has them: the triangle's rows within each group.
    const auto& rows = shape->rows;
    for (std::size_t i = 0; i < rows.size();) {
      const int y = by + rows[i][0];
      if (y < row0 || y >= row1) {
        ++i;
        continue;
      }
      const int group = group_of_row[y - row0];
      std::size_t j = i;
      left.clear(), right.clear();
      long long pixels = 0, unclipped = 0;
      for (; j < rows.size() && by + rows[j][0] < row1 && group_of_row[by + rows[j][0] - row0] == group; ++j) {
        left.push_back(std::clamp(bx + rows[j][1], 0, W)), right.push_back(std::clamp(bx + rows[j][2], 0, W));
        pixels += right.back() - left.back(), unclipped += rows[j][2] - rows[j][1];
      }
      if (pixels > 0) {
        const Piece<CT, true> piece(scene, t, id, p, true, pixels);
        if (!piece.shader.by_power && !shape->monomials.empty() && pixels == unclipped) {
          // The Bernstein form from the shape's monomials, pixels paired in
          // reading order (as draw_bernstein; pairing leaves the bits alone).
          const auto& q = shape->placed;
          const auto& m = shape->monomials;
          const std::size_t end = shape->row_first[j];
          std::size_t k = shape->row_first[i];
          for (; k + 1 < end; k += 2) {
            v2d pair[10];
            for (int n = 0; n < 10; ++n) pair[n] = v2d{m[k][n], m[k + 1][n]};
            piece.shader.monomial_pair(pair, image + (origin + q[k].offset), image + (origin + q[k + 1].offset));
          }
          if (k < end) piece.shader.monomial_pixel(m[k].data(), image + (origin + q[k].offset));
        } else {
          piece.draw(y, static_cast<int>(j - i), left.data(), right.data(), out, shift);
        }
        counts.pixels += pixels;
        ++(piece.shader.by_power ? counts.power_pieces : counts.bernstein_pieces);
      }
      i = j;
    }
  }
}

}  // namespace ddt::raster
