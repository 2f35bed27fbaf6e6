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

struct RenderPlan::Prepared {
  Prepared(const Mesh2& mesh, const RenderGrid& grid) : geometry(mesh, grid) {}

  SceneGeometry geometry;
  bool fill_outside = true;
  bool every_point_used = false;
  std::vector<char> used;  // the mesh vertices of a triangle, when not every point is
  // Lattice meshes drawn by shape where the scale allows (draw_planned).
  bool shapes_possible = false;
  bool lattice = false;  // every vertex at one fractional position in output pixels, `phase`
  Point2 phase{0, 0};  // the vertices' fractional position in output pixels
  // Mesh vertices by the output row ceil(y) of their position, clamped to
  // [-1, height]: row r's are vertex_ids[first_vertex[r + 1], first_vertex[r + 2]).
  std::vector<index_t> vertex_ids, first_vertex;
  // Rows r where a group of rows starts in the whole grid (r = 0, or a
  // vertex in (r - 1, r]); rows r >= height count as starts.
  std::vector<unsigned char> group_starts;
  // Drawn by shape: the lowest and highest y of each chunk of triangles.
  static constexpr index_t shape_chunk = 1 << 12;
  std::vector<std::pair<double, double>> chunk_rows;
  // The lattice shapes met so far, linear and cubic, for table_channels[k] channels.
  mutable std::unique_ptr<ShapeTable> tables[2];
  mutable int table_channels[2] = {0, 0};

  // The vertices whose row ceil(y) is in [row0, row1).
  std::pair<const index_t*, const index_t*> vertices_of_rows(int row0, int row1) const {
    const int height = geometry.grid.height;
    const int a = std::clamp(row0, -1, height + 1) + 1, b = std::clamp(row1, -1, height + 1) + 1;
    return {vertex_ids.data() + first_vertex[a], vertex_ids.data() + first_vertex[std::max(a, b)]};
  }
  ShapeTable& shape_table(int C, bool cubic) const {
    const int k = cubic ? 1 : 0;
    if (!tables[k] || table_channels[k] != C) {
      tables[k] = std::make_unique<ShapeTable>(static_cast<std::ptrdiff_t>(geometry.grid.width) * C, C, cubic);
      table_channels[k] = C;
    }
    return *tables[k];
  }
};

RenderPlan::RenderPlan(const Mesh2& mesh, const RenderGrid& grid, bool fill_outside)
    : prepared_(std::make_unique<Prepared>(mesh, grid)) {
  Prepared& plan = *prepared_;
  SceneGeometry& scene = plan.geometry;
  plan.fill_outside = fill_outside;
  scene.V = static_cast<index_t>(mesh.points.size());
  scene.T = mesh.triangle_count();
  if (scene.T == 0) return;  // collinear points: no geometry
  scene.hull = hull_half_edges(mesh, &plan.every_point_used);
  if (fill_outside) add_rim(scene);
  // Half-edges 3t + k of the mesh and the rim are index_t.
  if (3 * (static_cast<long long>(scene.T) + static_cast<long long>(scene.rim_tris.size() / 3)) >
      std::numeric_limits<index_t>::max())
    throw Error("render_mesh: the mesh is too large to render in one piece (render it in bands of rows)");
  std::atomic<bool> exact{grid.width <= 32768 && grid.height <= 32768};
  const Point2 first_position = scene.pos(0);
  const Point2 phase{first_position.x - std::floor(first_position.x), first_position.y - std::floor(first_position.y)};
  std::atomic<bool> lattice{grid.by_shapes};
  tbb::parallel_for(tbb::blocked_range<index_t>(0, scene.V, 1 << 16), [&](const tbb::blocked_range<index_t>& r) {
    bool all_exact = exact.load(std::memory_order_relaxed), on_lattice = lattice.load(std::memory_order_relaxed);
    for (index_t v = r.begin(); v < r.end(); ++v) {
      const Point2 p = scene.pos(v);
      if (all_exact && (!exact_coordinate(p.x) || !exact_coordinate(p.y))) all_exact = exact = false;
      // Exact coordinates are below 2^15: floor_int holds them.
      if (on_lattice && (!all_exact || p.x - floor_int(p.x) != phase.x || p.y - floor_int(p.y) != phase.y))
        on_lattice = lattice = false;
    }
  });
  scene.mesh_exact = exact;
  plan.lattice = lattice;
  plan.phase = phase;
  scene.rim_exact.resize(scene.rim_points.size());
  for (std::size_t i = 0; i < scene.rim_points.size(); ++i) {
    const Point2 p = scene.pos(scene.V + static_cast<index_t>(i));
    scene.rim_exact[i] = scene.mesh_exact && exact_coordinate(p.x) && exact_coordinate(p.y);
  }
  const double output_per_input = grid.scale_x * grid.scale_y;  // pixels per input unit area
  plan.shapes_possible = scene.mesh_exact && lattice && (!fill_outside || scene.hull_convex) &&
                         output_per_input <= std::max(shape_max_scale2_cubic, shape_max_scale2_linear) &&
                         shapes_repeat(scene);

  // The vertices by row: a counting sort on ceil(y).
  const int height = grid.height;
  auto row_key = [&](index_t v) { return std::clamp(ceil_int(clamp_pixels(scene.pos(v).y)), -1, height) + 1; };
  plan.first_vertex.assign(static_cast<std::size_t>(height) + 3, 0);
  for (index_t v = 0; v < scene.V; ++v) ++plan.first_vertex[row_key(v) + 1];
  for (int r = 0; r + 1 < static_cast<int>(plan.first_vertex.size()); ++r) plan.first_vertex[r + 1] += plan.first_vertex[r];
  plan.vertex_ids.resize(scene.V);
  {
    std::vector<index_t> next(plan.first_vertex.begin(), plan.first_vertex.end() - 1);
    for (index_t v = 0; v < scene.V; ++v) plan.vertex_ids[next[row_key(v)]++] = v;
  }
  plan.group_starts.assign(static_cast<std::size_t>(height) + 1, 0);
  plan.group_starts[0] = plan.group_starts[height] = 1;
  for (int r = 1; r < height; ++r)
    if (plan.first_vertex[r + 1] != plan.first_vertex[r + 2]) plan.group_starts[r] = 1;
  for (std::size_t i = 0; i < scene.rim_points.size(); ++i) {
    const Point2 p = scene.pos(scene.V + static_cast<index_t>(i));
    if (p.y > 0 && p.y <= height - 1) plan.group_starts[ceil_int(p.y)] = 1;
  }
  if (!plan.every_point_used) {
    plan.used.assign(scene.V, 0);
    for (index_t v : mesh.tri) plan.used[v] = 1;
  }
  if (plan.shapes_possible) {
    const index_t chunks = (scene.T + Prepared::shape_chunk - 1) / Prepared::shape_chunk;
    plan.chunk_rows.resize(chunks);
    tbb::parallel_for(index_t(0), chunks, [&](index_t k) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      const index_t t1 = std::min(scene.T, (k + 1) * Prepared::shape_chunk);
      for (index_t t = k * Prepared::shape_chunk; t < t1; ++t) {
        index_t id[3];
        scene.corners(t, id);
        for (const index_t v : id) lo = std::min(lo, scene.pos(v).y), hi = std::max(hi, scene.pos(v).y);
      }
      plan.chunk_rows[k] = {lo, hi};
    });
  }
}

bool RenderPlan::adds_windows_of_values() const {
  return prepared_->geometry.T > 0 && prepared_->geometry.hull_convex;
}

int RenderPlan::window_boundary(int row) const {
  const std::vector<unsigned char>& starts = prepared_->group_starts;
  const int height = prepared_->geometry.grid.height;
  if (starts.empty()) return std::clamp(row, 0, height);  // collinear points: no groups
  row = std::clamp(row, 0, height);
  while (!starts[row]) ++row;
  return row;
}

int RenderPlan::window_start(int row) const {
  const std::vector<unsigned char>& starts = prepared_->group_starts;
  const int height = prepared_->geometry.grid.height;
  row = std::clamp(row, 0, height);
  if (starts.empty()) return row;
  while (!starts[row]) --row;
  return row;
}

RenderPlan::~RenderPlan() = default;
RenderPlan::RenderPlan(RenderPlan&&) noexcept = default;
RenderPlan& RenderPlan::operator=(RenderPlan&&) noexcept = default;

namespace {

// render_mesh_into and add_mesh_render_into: `add` adds the linear surface
// to the pixels' values instead of writing it.
void draw_planned(Image& out, int out_row, const RenderPlan::Prepared& plan, const std::vector<float>& values, int C,
                  int first_row, int grid_rows, RenderStats* stats, const std::vector<float>* gradients,
                  Progress* progress, bool add, const VertexValues* window = nullptr,
                  const VertexValues* gradient_window = nullptr) {
  const SceneGeometry& geometry = plan.geometry;
  const Mesh2& mesh = geometry.mesh;
  const RenderGrid& grid = geometry.grid;
  const bool fill_outside = plan.fill_outside;
  if (gradients && (gradients->size() != values.size() * 2 || C > max_channels))
    throw Error("render_mesh: cubic mode needs #V x C x 2 gradients and at most 16 channels");
  if (C > max_channels) throw Error("render_mesh: at most 16 channels");
  const bool cubic = gradients || gradient_window;
  auto malformed = [](const VertexValues& w) { return w.first < 0 || w.end < w.first || (w.end > w.first && !w.data); };
  if (gradient_window) {
    if (add || gradients || window)
      throw Error("render_mesh: a window of gradients draws only a cubic surface");
    if (malformed(*gradient_window)) throw Error("render_mesh: a window of gradients without its gradients");
  }
  if (window) {
    // Only the walk and the shapes read values by vertex; the other paths read them all.
    if (!add || gradients || geometry.T == 0 || !geometry.hull_convex)
      throw Error("render_mesh: a window of values draws only an added surface on a mesh with a convex hull");
    if (malformed(*window)) throw Error("render_mesh: a window of values without its values");
  } else if (values.size() < static_cast<std::size_t>(geometry.V) * C) {
    throw Error("render_mesh: fewer values than vertices");
  }
  if (add && !fill_outside) throw Error("render_mesh: an added render draws the rim");
  RenderStats local;
  const int row0 = grid_rows < 0 ? 0 : std::clamp(first_row, 0, grid.height);
  const int row1 = grid_rows < 0 ? grid.height : std::clamp(first_row + grid_rows, row0, grid.height);
  if (out.width != grid.width || out.channels != C || out_row < 0 || out_row + (row1 - row0) > out.height)
    throw Error("render_mesh_into: the image does not hold the rows");
  // Where pixels are not drawn once each by the walk (collinear points; a
  // hull that is not convex, whose rim can reach over the mesh), an added
  // surface is drawn apart, then added.
  auto drawn_apart_then_added = [&] {
    Image rows(grid.width, row1 - row0, C);
    draw_planned(rows, 0, plan, values, C, row0, row1 - row0, stats, nullptr, progress, false);
    float* o = &out.pixels[out.index(0, out_row)];
    for (std::size_t i = 0; i < rows.pixels.size(); ++i) o[i] += rows.pixels[i];
  };
  if (geometry.T == 0) {
    if (add) return drawn_apart_then_added();
    if (stats) *stats = local;
    if (!fill_outside) return;
    const Image line = render_collinear(mesh, values, C, grid, row0, row1);
    std::copy(line.pixels.begin(), line.pixels.end(), out.pixels.begin() + static_cast<std::ptrdiff_t>(out.index(0, out_row)));
    return;
  }
  if (add && !geometry.hull_convex) return drawn_apart_then_added();
  // Grid row y goes to out row y - shift.
  const int shift = row0 - out_row;
  Scene scene(geometry, values, C);
  scene.window = window;
  scene.gradients = gradients;
  scene.gradient_window = gradient_window;
  scene.add = add;
  if (cubic && fill_outside) scene.rim_patches = make_rim_patches(scene);
  local.triangles = scene.T;
  local.rim_triangles = static_cast<long long>(geometry.rim_tris.size() / 3);
  const Point2 phase = plan.phase;
  const double output_per_input = grid.scale_x * grid.scale_y;  // pixels per input unit area
  const bool by_shape =
      plan.shapes_possible && output_per_input <= (cubic ? shape_max_scale2_cubic : shape_max_scale2_linear);
  // Rows of groups: row r starts a group when r == row0 or a vertex lies in
  // (r - 1, r] (the plan's group_starts); within a group the same triangles
  // cross every row.
  const int rows = row1 - row0;
  std::vector<int> group_first, group_of_row(rows);
  for (int r = 0; r < rows; ++r) {
    if (r == 0 || plan.group_starts[row0 + r]) group_first.push_back(row0 + r);
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
    for (std::size_t i = 0; i < geometry.rim_twin.size(); ++i)
      if (geometry.rim_twin[i] == no_edge) add_starts(3 * scene.T + static_cast<index_t>(i));
    // Drawn by shape, the mesh ends the walks: the rim beyond it is walked
    // from the hull.
    if (by_shape)
      for (index_t e : geometry.hull)
        if (const index_t rim = scene.twin(e); rim != no_edge) add_starts(rim);
  } else if (!by_shape) {
    for (index_t e : geometry.hull) add_starts(e);
  }
  std::sort(starts.begin(), starts.end());
  std::vector<std::size_t> starts_of(groups + 1, 0);  // group k: starts[starts_of[k], starts_of[k + 1])
  for (const auto& s : starts) ++starts_of[s.first + 1];
  for (int k = 0; k < groups; ++k) starts_of[k + 1] += starts_of[k];

  // The output pixel a vertex of a triangle falls on, in the rows drawn (else null).
  auto vertex_pixel = [&](index_t v) -> float* {
    if (!plan.used.empty() && !plan.used[v]) return nullptr;
    const Point2 p = scene.pos(v);
    if (p.x != std::floor(p.x) || p.y != std::floor(p.y)) return nullptr;
    if (p.x < 0 || p.y < row0 || p.x >= grid.width || p.y >= row1) return nullptr;
    return &out.pixels[out.index(static_cast<int>(p.x), static_cast<int>(p.y) - shift)];
  };
  // Only the vertices of the rows drawn can fall on their pixels.
  const auto window_range = plan.vertices_of_rows(row0, row1);
  const index_t* const window_first = window_range.first;  // a plain name: lambdas below capture it
  const std::size_t window_vertices = static_cast<std::size_t>(window_range.second - window_first);
  std::vector<float> pixels_before;
  if (add && !(plan.lattice && (phase.x != 0 || phase.y != 0))) {  // else no vertex is on a pixel centre
    pixels_before.resize(window_vertices * C);
    tbb::parallel_for(std::size_t(0), window_vertices, [&](std::size_t i) {
      if (const float* px = vertex_pixel(window_first[i])) std::copy_n(px, C, &pixels_before[i * C]);
    });
  }

  // Drawn by shape: the chunks of triangles that reach the rows.
  std::vector<index_t> chunks;
  if (by_shape)
    for (std::size_t k = 0; k < plan.chunk_rows.size(); ++k)
      if (!(plan.chunk_rows[k].second < row0 || plan.chunk_rows[k].first >= row1)) chunks.push_back(static_cast<index_t>(k));
  ShapeTable* shapes = by_shape ? &plan.shape_table(C, cubic) : nullptr;
  if (progress) progress->begin("render", groups + static_cast<long long>(chunks.size()));
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
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks.size()), [&](const tbb::blocked_range<std::size_t>& range) {
      Shape own;  // a shape not kept in the table
      std::vector<int> left, right;
      DrawCounts counts;
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        const index_t t0 = chunks[i] * RenderPlan::Prepared::shape_chunk,
                      t1 = std::min<index_t>(scene.T, t0 + RenderPlan::Prepared::shape_chunk);
        for (index_t t = t0; t < t1; ++t)
          draw_by_shape<CT, is_cubic>(scene, t, *shapes, phase, group_of_row, row0, row1, shift, out, own, left,
                                      right, counts);
      }
      drawn += counts.pixels, shaped += counts.shaped_triangles;
      power_pieces += counts.power_pieces, bernstein_pieces += counts.bernstein_pieces;
      if (progress) progress->add(range.size());
    });
  };
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
  tbb::parallel_for(std::size_t(0), window_vertices, [&](std::size_t i) {
    const index_t v = window_first[i];
    float* px = vertex_pixel(v);
    if (!px) return;
    const float* z = scene.value(v);
    const float* before = add ? &pixels_before[i * C] : nullptr;
    for (int c = 0; c < C; ++c) px[c] = add ? before[c] + z[c] : z[c];
  });

  if (stats) *stats = local;
}

}  // namespace

void render_mesh_into(Image& out, int out_row, const RenderPlan& plan, const std::vector<float>& values, int C,
                      int first_row, int rows, RenderStats* stats, const std::vector<float>* gradients,
                      Progress* progress) {
  draw_planned(out, out_row, plan.prepared(), values, C, first_row, rows, stats, gradients, progress, false);
}

void render_mesh_into(Image& out, int out_row, const RenderPlan& plan, const std::vector<float>& values, int C,
                      int first_row, int rows, const VertexValues& gradients, RenderStats* stats) {
  draw_planned(out, out_row, plan.prepared(), values, C, first_row, rows, stats, nullptr, nullptr, false, nullptr,
               &gradients);
}

void add_mesh_render_into(Image& out, int out_row, const RenderPlan& plan, const std::vector<float>& values, int C,
                          int first_row, int rows, RenderStats* stats) {
  draw_planned(out, out_row, plan.prepared(), values, C, first_row, rows, stats, nullptr, nullptr, true);
}

void add_mesh_render_into(Image& out, int out_row, const RenderPlan& plan, const VertexValues& values, int C,
                          int first_row, int rows, RenderStats* stats) {
  static const std::vector<float> none;
  draw_planned(out, out_row, plan.prepared(), none, C, first_row, rows, stats, nullptr, nullptr, true, &values);
}

void render_mesh_into(Image& out, int out_row, const Mesh2& mesh, const std::vector<float>& values, int C,
                      const RenderGrid& grid, RenderStats* stats, bool fill_outside, const std::vector<float>* gradients,
                      Progress* progress) {
  const RenderPlan plan(mesh, grid, fill_outside);
  render_mesh_into(out, out_row, plan, values, C, grid.first_row, grid.rows, stats, gradients, progress);
}

void add_mesh_render_into(Image& out, int out_row, const Mesh2& mesh, const std::vector<float>& values, int C,
                          const RenderGrid& grid, RenderStats* stats) {
  const RenderPlan plan(mesh, grid, true);
  add_mesh_render_into(out, out_row, plan, values, C, grid.first_row, grid.rows, stats);
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
