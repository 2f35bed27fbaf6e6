#include "image/rasterizer.hpp"

#include "image/raster/lattice_shapes.hpp"
#include "image/raster/scene.hpp"
#include "image/raster/shader.hpp"
#include "image/raster/walk.hpp"
#include "util/error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>

namespace ddt {
using namespace raster;

namespace {

// render_mesh_into and add_mesh_render_into: `add` adds the linear surface
// to the pixels' values instead of writing it.
void draw_mesh(Image& out, int out_row, const Mesh2& mesh, const std::vector<float>& values, int C,
               const RenderGrid& grid, RenderStats* stats, bool fill_outside, const std::vector<float>* gradients,
               Progress* progress, bool add) {
  if (gradients && (gradients->size() != values.size() * 2 || C > max_channels))
    throw Error("render_mesh: cubic mode needs #V x C x 2 gradients and at most 16 channels");
  if (C > max_channels) throw Error("render_mesh: at most 16 channels");
  RenderStats local;
  const int row0 = grid.rows < 0 ? 0 : std::clamp(grid.first_row, 0, grid.height);
  const int row1 = grid.rows < 0 ? grid.height : std::clamp(grid.first_row + grid.rows, row0, grid.height);
  if (out.width != grid.width || out.channels != C || out_row < 0 || out_row + (row1 - row0) > out.height)
    throw Error("render_mesh_into: the image does not hold the rows");
  // Where pixels are not drawn once each by the walk (collinear points; a
  // hull that is not convex, whose rim can reach over the mesh), an added
  // surface is drawn apart, then added.
  auto drawn_apart_then_added = [&] {
    Image rows(grid.width, row1 - row0, C);
    draw_mesh(rows, 0, mesh, values, C, grid, stats, fill_outside, nullptr, progress, false);
    float* o = &out.pixels[out.index(0, out_row)];
    for (std::size_t i = 0; i < rows.pixels.size(); ++i) o[i] += rows.pixels[i];
  };
  if (mesh.triangle_count() == 0) {
    if (add) return drawn_apart_then_added();
    if (stats) *stats = local;
    if (!fill_outside) return;
    const Image line = render_collinear(mesh, values, C, grid, row0, row1);
    std::copy(line.pixels.begin(), line.pixels.end(), out.pixels.begin() + static_cast<std::ptrdiff_t>(out.index(0, out_row)));
    return;
  }
  // Grid row y goes to out row y - shift.
  const int shift = row0 - out_row;
  Scene scene{mesh, values, C, grid};
  scene.gradients = gradients;
  scene.add = add;
  scene.V = static_cast<index_t>(mesh.points.size());
  scene.T = mesh.triangle_count();
  bool every_point_used = false;
  scene.hull = hull_half_edges(mesh, &every_point_used);
  if (fill_outside) add_rim(scene);
  if (add && !scene.hull_convex) return drawn_apart_then_added();
  // Half-edges 3t + k of the mesh and the rim are index_t.
  if (3 * (static_cast<long long>(scene.T) + static_cast<long long>(scene.rim_tris.size() / 3)) >
      std::numeric_limits<index_t>::max())
    throw Error("render_mesh: the mesh is too large to render in one piece (render it in bands of rows)");
  local.triangles = scene.T;
  local.rim_triangles = static_cast<long long>(scene.rim_tris.size() / 3);
  std::atomic<bool> exact{grid.width <= 32768 && grid.height <= 32768};
  const Point2 first_position = scene.pos(0);
  const Point2 phase{first_position.x - std::floor(first_position.x), first_position.y - std::floor(first_position.y)};
  std::atomic<bool> lattice{grid.by_shapes};
  // Rows of groups: row r starts a group when r == row0 or a vertex lies in
  // (r - 1, r]; within a group the same triangles cross every row.
  const int rows = row1 - row0;
  std::vector<unsigned char> group_start(static_cast<std::size_t>(rows) + 1, 0);
  group_start[0] = 1;
  auto mark_row = [&](const Point2& p) {
    if (p.y > row0 && p.y <= row1 - 1)
      std::atomic_ref<unsigned char>(group_start[ceil_int(p.y) - row0]).store(1, std::memory_order_relaxed);
  };
  tbb::parallel_for(tbb::blocked_range<index_t>(0, scene.V, 1 << 16), [&](const tbb::blocked_range<index_t>& r) {
    bool all_exact = exact.load(std::memory_order_relaxed), on_lattice = lattice.load(std::memory_order_relaxed);
    for (index_t v = r.begin(); v < r.end(); ++v) {
      const Point2 p = scene.pos(v);
      mark_row(p);
      if (all_exact && (!exact_coordinate(p.x) || !exact_coordinate(p.y))) all_exact = exact = false;
      // Exact coordinates are below 2^15: floor_int holds them.
      if (on_lattice && (!all_exact || p.x - floor_int(p.x) != phase.x || p.y - floor_int(p.y) != phase.y))
        on_lattice = lattice = false;
    }
  });
  scene.mesh_exact = exact;
  const double output_per_input = grid.scale_x * grid.scale_y;  // pixels per input unit area
  const bool by_shape = scene.mesh_exact && lattice && (!fill_outside || scene.hull_convex) &&
                        output_per_input <= (gradients ? shape_max_scale2_cubic : shape_max_scale2_linear) &&
                        shapes_repeat(scene);
  scene.rim_exact.resize(scene.rim_points.size());
  for (std::size_t i = 0; i < scene.rim_points.size(); ++i) {
    const Point2 p = scene.pos(scene.V + static_cast<index_t>(i));
    mark_row(p);
    scene.rim_exact[i] = scene.mesh_exact && exact_coordinate(p.x) && exact_coordinate(p.y);
  }
  std::vector<int> group_first, group_of_row(rows);
  for (int r = 0; r < rows; ++r) {
    if (group_start[r]) group_first.push_back(row0 + r);
    group_of_row[r] = static_cast<int>(group_first.size()) - 1;
  }
  const int groups = static_cast<int>(group_first.size());
  group_first.push_back(row1);

  // Each group's walks start at the upward boundary half-edges crossing it
  // (the left bounds of the leftmost triangles: one, on a convex boundary).
  std::vector<std::pair<int, index_t>> starts;  // (group, half-edge)
  auto add_starts = [&](index_t e) {
    const Point2 u = scene.pos(scene.tail(e)), v = scene.pos(scene.tail(next_edge(e)));
    if (!(v.y < u.y)) return;
    // rows h with v.y <= h < u.y: whole groups, since u and v start groups
    const int h0 = std::max(row0, ceil_int(clamp_pixels(v.y))), h1 = std::min(row1 - 1, ceil_int(clamp_pixels(u.y)) - 1);
    if (h0 > h1) return;
    for (int k = group_of_row[h0 - row0]; k <= group_of_row[h1 - row0]; ++k) starts.emplace_back(k, e);
  };
  if (fill_outside) {
    for (std::size_t i = 0; i < scene.rim_twin.size(); ++i)
      if (scene.rim_twin[i] == no_edge) add_starts(3 * scene.T + static_cast<index_t>(i));
    // Drawn by shape, the mesh ends the walks: the rim beyond it is walked
    // from the hull.
    if (by_shape)
      for (index_t e : scene.hull)
        if (const index_t rim = scene.twin(e); rim != no_edge) add_starts(rim);
  } else if (!by_shape) {
    for (index_t e : scene.hull) add_starts(e);
  }
  std::sort(starts.begin(), starts.end());
  std::vector<std::size_t> starts_of(groups + 1, 0);  // group k: starts[starts_of[k], starts_of[k + 1])
  for (const auto& s : starts) ++starts_of[s.first + 1];
  for (int k = 0; k < groups; ++k) starts_of[k + 1] += starts_of[k];

  // The output pixel a vertex of a triangle falls on, in the rows drawn (else null).
  std::vector<char> used;
  if (!every_point_used) {
    used.assign(scene.V, 0);
    for (index_t v : mesh.tri) used[v] = 1;
  }
  auto vertex_pixel = [&](index_t v) -> float* {
    if (!used.empty() && !used[v]) return nullptr;
    const Point2 p = scene.pos(v);
    if (p.x != std::floor(p.x) || p.y != std::floor(p.y)) return nullptr;
    if (p.x < 0 || p.y < row0 || p.x >= grid.width || p.y >= row1) return nullptr;
    return &out.pixels[out.index(static_cast<int>(p.x), static_cast<int>(p.y) - shift)];
  };
  std::vector<float> pixels_before;
  if (add && !(lattice && (phase.x != 0 || phase.y != 0))) {  // else no vertex is on a pixel centre
    pixels_before.resize(static_cast<std::size_t>(scene.V) * C);
    tbb::parallel_for(index_t(0), scene.V, [&](index_t v) {
      if (const float* px = vertex_pixel(v)) std::copy_n(px, C, &pixels_before[static_cast<std::size_t>(v) * C]);
    });
  }

  constexpr index_t shape_chunk = 1 << 12;  // triangles
  const int shape_chunks = by_shape ? static_cast<int>((scene.T + shape_chunk - 1) / shape_chunk) : 0;
  std::optional<ShapeTable> shapes;  // 256 KB of slots: only when used
  if (by_shape) shapes.emplace(static_cast<std::ptrdiff_t>(grid.width) * C, C, gradients != nullptr);
  if (progress) progress->begin("render", groups + shape_chunks);
  std::atomic<long long> drawn{0}, power_pieces{0}, bernstein_pieces{0}, shaped{0};
  auto draw_groups = [&](auto channels, auto cubic) {
    constexpr int CT = decltype(channels)::value;
    constexpr bool is_cubic = decltype(cubic)::value;
    tbb::parallel_for(tbb::blocked_range<int>(0, groups), [&](const tbb::blocked_range<int>& range) {
      std::vector<int> left, right;
      Walk walks[walk_batch];
      int walk_group[walk_batch];
      DrawCounts counts;
      const std::size_t end = starts_of[range.end()];
      for (std::size_t i = starts_of[range.begin()]; i < end; i += walk_batch) {
        const int n = static_cast<int>(std::min<std::size_t>(walk_batch, end - i));
        for (int j = 0; j < n; ++j) {
          walk_group[j] = starts[i + j].first;
          walks[j].start = starts[i + j].second, walks[j].g = group_first[walk_group[j]];
        }
        trace_walks(scene, walks, n, by_shape ? scene.T : 0);
        for (int j = 0; j < n; ++j) {
          const int k = walk_group[j], m = group_first[k + 1] - group_first[k];
          draw_walk<CT, is_cubic>(scene, walks[j], m, shift, out, left, right, counts);
        }
      }
      drawn += counts.pixels;
      power_pieces += counts.power_pieces, bernstein_pieces += counts.bernstein_pieces;
      if (progress) progress->add(range.size());
    });
    tbb::parallel_for(tbb::blocked_range<int>(0, shape_chunks), [&](const tbb::blocked_range<int>& range) {
      Shape own;  // a shape not kept in the table
      std::vector<int> left, right;
      DrawCounts counts;
      const index_t t0 = range.begin() * shape_chunk, t1 = std::min<index_t>(scene.T, range.end() * shape_chunk);
      for (index_t t = t0; t < t1; ++t)
        draw_by_shape<CT, is_cubic>(scene, t, *shapes, phase, group_of_row, row0, row1, shift, out, own, left, right,
                                    counts);
      drawn += counts.pixels, shaped += counts.shaped_triangles;
      power_pieces += counts.power_pieces, bernstein_pieces += counts.bernstein_pieces;
      if (progress) progress->add(range.size());
    });
  };
  const bool cubic = gradients != nullptr;
  switch (C) {
    case 1: cubic ? draw_groups(channels<1>{}, std::true_type{}) : draw_groups(channels<1>{}, std::false_type{}); break;
    case 3: cubic ? draw_groups(channels<3>{}, std::true_type{}) : draw_groups(channels<3>{}, std::false_type{}); break;
    case 4: cubic ? draw_groups(channels<4>{}, std::true_type{}) : draw_groups(channels<4>{}, std::false_type{}); break;
    default: cubic ? draw_groups(channels<0>{}, std::true_type{}) : draw_groups(channels<0>{}, std::false_type{});
  }
  local.power_pieces = power_pieces, local.bernstein_pieces = bernstein_pieces;
  local.shaped_triangles = shaped;
  local.shapes = shapes ? static_cast<long long>(shapes->size()) : 0;
  local.uncovered = static_cast<long long>(rows) * grid.width - drawn;

  // Samples that fall on pixel centres are written exactly (the plane and
  // the patch equal the vertex value there up to rounding); added, to the
  // pixel's value from before the drawing.
  tbb::parallel_for(index_t(0), scene.V, [&](index_t v) {
    float* px = vertex_pixel(v);
    if (!px) return;
    const float* z = scene.value(v);
    const float* before = add ? &pixels_before[static_cast<std::size_t>(v) * C] : nullptr;
    for (int c = 0; c < C; ++c) px[c] = add ? before[c] + z[c] : z[c];
  });

  if (stats) *stats = local;
}

}  // namespace

void render_mesh_into(Image& out, int out_row, const Mesh2& mesh, const std::vector<float>& values, int C,
                      const RenderGrid& grid, RenderStats* stats, bool fill_outside, const std::vector<float>* gradients,
                      Progress* progress) {
  draw_mesh(out, out_row, mesh, values, C, grid, stats, fill_outside, gradients, progress, false);
}

void add_mesh_render_into(Image& out, int out_row, const Mesh2& mesh, const std::vector<float>& values, int C,
                          const RenderGrid& grid, RenderStats* stats) {
  draw_mesh(out, out_row, mesh, values, C, grid, stats, true, nullptr, nullptr, true);
}

Image render_mesh(const Mesh2& mesh, const std::vector<float>& values, int C, const RenderGrid& grid,
                  RenderStats* stats, bool fill_outside, float outside_value, const std::vector<float>* gradients,
                  Progress* progress) {
  const int row0 = grid.rows < 0 ? 0 : std::clamp(grid.first_row, 0, grid.height);
  const int row1 = grid.rows < 0 ? grid.height : std::clamp(grid.first_row + grid.rows, row0, grid.height);
  Image out(grid.width, row1 - row0, C, outside_value);
  render_mesh_into(out, 0, mesh, values, C, grid, stats, fill_outside, gradients, progress);
  return out;
}

}  // namespace ddt
