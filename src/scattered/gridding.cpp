#include "scattered/gridding.hpp"

#include "core/costs.hpp"
#include "util/error.hpp"
#include "image/optimizer.hpp"
#include "image/optimizer_choice.hpp"
#include "image/rasterizer.hpp"
#include "image/triangulation.hpp"
#include "pipeline/drive_channels.hpp"
#include "util/timing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ddt {
namespace {

// What drives the flips (GridOptions::cost_channel): all channels, their
// luminance, or one of them.
DriveChannels drive_of_points(int C, int cost_channel) {
  DriveChannels d;
  if (cost_channel == cost_channel_sum) {
    if (C > max_cost_channels)
      throw Error("the cost takes at most " + std::to_string(max_cost_channels) + " channels; the points have " +
                  std::to_string(C) + " (pick one with --cost-channel)");
    for (int c = 0; c < C; ++c) d.colour.push_back(c);
    d.K = C;
    d.identity = true;
    return d;
  }
  d.K = 1;
  if (cost_channel == cost_channel_luma) {
    if (C < 3) throw Error("--cost-channel luma needs three value channels (R, G, B); the points have " + std::to_string(C));
    d.colour = {0, 1, 2};
    d.luma = true;
    return d;
  }
  if (cost_channel < 0 || cost_channel >= C)
    throw Error("--cost-channel " + std::to_string(cost_channel + 1) + ": the points have " + std::to_string(C) +
                " value channel" + (C == 1 ? "" : "s"));
  d.colour = {cost_channel};
  return d;
}

// v clamped to [-1, n] before the conversion (far-away positions must not
// overflow an int).
int to_index(double v, int n) { return static_cast<int>(std::clamp(v, -1.0, static_cast<double>(n))); }

// Per row, the range of columns whose pixel centre lies inside the mesh's
// convex hull or within `tol` pixels of it. Positions go to pixel space
// exactly as the rasterizer maps them (pixel centres at integers), so a
// sample that lands on a pixel centre is judged like the rasterizer judges it.
// A pixel is inside when, for every hull edge u->v (interior on the left),
// cross(v - u, p - u) >= -tol |v - u|; only edges whose rows come within a
// pixel of the row can bind (the hull is convex), so edges are binned by row.
void hull_spans(const Mesh2& mesh, const RenderGrid& grid, double tol, std::vector<int>& first,
                std::vector<int>& last) {
  const int W = grid.width, H = grid.height;
  auto to_pixel = [&](const Point2& p) {
    return Point2{(p.x - grid.origin_x) * grid.scale_x - 0.5, (p.y - grid.origin_y) * grid.scale_y - 0.5};
  };
  struct Edge {
    Point2 u, v;
  };
  std::vector<Edge> edges;
  double top = INFINITY, bottom = -INFINITY;
  for (index_t e : hull_half_edges(mesh)) {
    const Edge ed{to_pixel(mesh.points[mesh.tri[e]]), to_pixel(mesh.points[mesh.tri[next_edge(e)]])};
    top = std::min(top, ed.u.y);
    bottom = std::max(bottom, ed.u.y);
    edges.push_back(ed);
  }
  std::vector<std::vector<int>> by_row(H);
  for (int k = 0; k < static_cast<int>(edges.size()); ++k) {
    const double lo = std::min(edges[k].u.y, edges[k].v.y) - 1, hi = std::max(edges[k].u.y, edges[k].v.y) + 1;
    const int r0 = std::max(0, to_index(std::ceil(lo), H)), r1 = std::min(H - 1, to_index(std::floor(hi), H));
    for (int r = r0; r <= r1; ++r) by_row[r].push_back(k);
  }
  first.assign(H, 0);
  last.assign(H, -1);
  for (int Y = 0; Y < H; ++Y) {
    if (Y < top - tol || Y > bottom + tol) continue;
    double lo = -INFINITY, hi = INFINITY;
    bool empty = false;
    for (int k : by_row[Y]) {
      const Point2 &u = edges[k].u, &v = edges[k].v;
      const double dx = v.x - u.x, dy = v.y - u.y;
      // cross(v - u, (X, Y) - u) + tol |v - u| >= 0  <=>  dy * X <= c
      const double c = dx * (Y - u.y) + dy * u.x + tol * std::hypot(dx, dy);
      if (dy > 0) hi = std::min(hi, c / dy);
      else if (dy < 0) lo = std::max(lo, c / dy);
      else if (c < 0) empty = true;
    }
    if (empty || !(lo <= hi)) continue;
    first[Y] = std::max(0, to_index(std::ceil(lo), W));
    last[Y] = std::min(W - 1, to_index(std::floor(hi), W));
  }
}

// The triangulation and the render compute with sums and differences of
// coordinates: an extent (of the points and the bounds, on either axis)
// past max_extent overflows them (0..1e308 rendered every pixel 0). The
// flips' costs multiply two coordinate differences (areas, gradients): past
// max_flip_extent, or below its inverse, those overflow or underflow and the
// flips go wrong without a sign (measured: a Halton set scaled by 1e155 or
// 1e-160 flips otherwise than at scale 1). Such input is refused rather than
// gridded wrongly. Offsets are free: 1e300 plus a 1e290 extent grids as 0
// plus 1 does, to rounding.
constexpr double max_extent = 1e307, max_flip_extent = 1e150;

void check_representable(const std::vector<Point2>& points, const GridBounds& b, bool optimize) {
  const GridBounds box = bounding_box(points);
  const double extent_x = std::max(b.xmax, box.xmax) - std::min(b.xmin, box.xmin);
  const double extent_y = std::max(b.ymax, box.ymax) - std::min(b.ymin, box.ymin);
  char line[240];
  if (!(extent_x <= max_extent) || !(extent_y <= max_extent)) {
    std::snprintf(line, sizeof line,
                  "the points and bounds span %.3g by %.3g, beyond the %.0e that double precision can grid "
                  "(shift or scale the coordinates)",
                  extent_x, extent_y, max_extent);
    throw Error(line);
  }
  if (!optimize) return;
  for (const double extent : {box.xmax - box.xmin, box.ymax - box.ymin})
    if (extent > max_flip_extent || (extent > 0 && extent < 1 / max_flip_extent)) {
      std::snprintf(line, sizeof line,
                    "the points span %.3g by %.3g: the flips' costs need spans within %.0e..%.0e in double "
                    "precision (scale the coordinates, or grid without flips)",
                    box.xmax - box.xmin, box.ymax - box.ymin, 1 / max_flip_extent, max_flip_extent);
      throw Error(line);
    }
}

// Inside the hull every grid value is a convex combination of the point
// values (the linear surface and the nearest hull point), so it lies within
// their range, channel by channel; a value outside it is an arithmetic
// failure, and the grid is refused instead of written.
void check_within_values(const Image& out, const std::vector<float>& values, int C, const std::vector<int>& first,
                         const std::vector<int>& last) {
  for (int c = 0; c < C; ++c) {
    float lo = INFINITY, hi = -INFINITY;
    for (std::size_t i = c; i < values.size(); i += C) lo = std::min(lo, values[i]), hi = std::max(hi, values[i]);
    const float slack = 1e-5f * std::max(1.0f, std::max(std::abs(lo), std::abs(hi)));
    for (int y = 0; y < out.height; ++y)
      for (int x = first[y]; x <= last[y]; ++x) {
        const float v = out.pixels[out.index(x, y) + c];
        if (!(v >= lo - slack && v <= hi + slack))
          throw Error("the grid could not be computed: the value at pixel (" + std::to_string(x) + ", " +
                      std::to_string(y) + ") leaves the range of the points' values (numeric overflow)");
      }
  }
}

}  // namespace

GridBounds bounding_box(const std::vector<Point2>& points) {
  GridBounds b{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (const Point2& p : points) {
    b.xmin = std::min(b.xmin, p.x), b.xmax = std::max(b.xmax, p.x);
    b.ymin = std::min(b.ymin, p.y), b.ymax = std::max(b.ymax, p.y);
  }
  return b;
}

Image grid_points(const std::vector<Point2>& points, const std::vector<float>& values, int C,
                  const GridOptions& options, GridStats* stats) {
  if (C < 1) throw Error("the points need at least one value channel");
  if (values.size() != points.size() * static_cast<std::size_t>(C))
    throw Error("grid_points: " + std::to_string(values.size()) + " values for " + std::to_string(points.size()) +
                " points of " + std::to_string(C) + " channels");
  if (options.width < 1 || options.height < 1) throw Error("the grid size must be at least 1x1");
  const CostFunction& cost = find_cost(options.cost);
  check_optimizer(options.optimizer, options.anneal);
  GridStats local;
  const StageRunner stages(options.log);
  auto log = [&](const std::string& line) { stages.log(line); };

  const GridBounds b = options.bounds ? *options.bounds : bounding_box(points);
  if (options.bounds) {
    if (!(std::isfinite(b.xmin) && std::isfinite(b.ymin) && std::isfinite(b.xmax) && std::isfinite(b.ymax)))
      throw Error("the bounds must be finite numbers");
    if (!(b.xmin < b.xmax) || !(b.ymin < b.ymax)) throw Error("the bounds need xmin < xmax and ymin < ymax");
  }
  check_representable(points, b, options.optimize);
  local.bounds = b;

  // Mirror y (exact) so that the rasterizer's rows, which run toward
  // increasing coordinates, run from ymax down to ymin.
  auto t0 = Clock::now();
  std::vector<Point2> mirrored(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) mirrored[i] = {points[i].x, -points[i].y};
  Mesh2 mesh = delaunay_triangulation(mirrored);
  local.seconds_triangulate = seconds_since(t0);
  if (mesh.triangle_count() == 0)
    throw Error("the points span no area: need at least three points not on one line (got " +
                std::to_string(points.size()) + " distinct positions)");
  local.points = static_cast<long long>(points.size());
  local.triangles = mesh.triangle_count();
  log("triangulate: " + std::to_string(points.size()) + " points, " + std::to_string(mesh.triangle_count()) +
      " triangles, " + std::to_string(local.seconds_triangulate) + " s");

  t0 = Clock::now();
  const DriveChannels drive = drive_of_points(C, options.cost_channel);  // validates even without flips
  if (options.optimize) {
    std::vector<float> own_drive;
    if (!drive.identity) own_drive = drive_values(values.data(), points.size(), C, drive);
    LawsonOptions lawson = lawson_options<LawsonOptions>(options);
    if (stages.logging())
      lawson.on_iteration = [&](int iteration, long long flips, double total) {
        char line[160];
        std::snprintf(line, sizeof line, "optimize: iteration %d, %lld flips, cost %.9g", iteration, flips, total);
        log(line);
      };
    local.take(run_optimizer(mesh, drive.identity ? values : own_drive, drive.K, cost, options.optimizer, options.anneal,
                             lawson, stages.logger()));
    local.seconds_optimize = seconds_since(t0);
    char line[200];
    std::snprintf(line, sizeof line, "optimize: cost %s, %d iterations, %lld flips, cost %.9g -> %.9g, %.3f s",
                  cost.name, local.iterations, local.flips, local.cost_before, local.cost_after,
                  local.seconds_optimize);
    log(line);
  }

  t0 = Clock::now();
  RenderGrid grid;
  grid.width = options.width;
  grid.height = options.height;
  grid.scale_x = options.width / (b.xmax - b.xmin);
  grid.scale_y = options.height / (b.ymax - b.ymin);
  grid.origin_x = b.xmin;
  grid.origin_y = -b.ymax;
  if (!std::isfinite(grid.scale_x) || !std::isfinite(grid.scale_y) || !(grid.scale_x > 0) || !(grid.scale_y > 0))
    throw Error("the bounds are too small for the grid size");
  RenderStats rs;
  // The rim outside the hull is drawn too (nearest hull value), so centres
  // within the tolerance of the hull have a value; the rest is masked below.
  Image surface = render_mesh(mesh, values, C, grid, &rs, true);
  std::vector<int> first, last;
  hull_spans(mesh, grid, options.hull_tolerance, first, last);

  const int out_c = C + (options.alpha ? 1 : 0);
  Image out(options.width, options.height, out_c, options.nodata);
  if (options.alpha)
    for (std::size_t i = 0; i < out.pixel_count(); ++i) out.pixels[i * out_c + C] = 0.0f;
  for (int y = 0; y < options.height; ++y) {
    for (int x = first[y]; x <= last[y]; ++x) {
      const float* src = &surface.pixels[surface.index(x, y)];
      float* dst = &out.pixels[out.index(x, y)];
      std::copy(src, src + C, dst);
      if (options.alpha) dst[C] = 1.0f;
    }
    local.inside_pixels += std::max(0, last[y] - first[y] + 1);
  }
  check_within_values(out, values, C, first, last);
  local.nodata_pixels = static_cast<long long>(out.pixel_count()) - local.inside_pixels;
  local.seconds_render = seconds_since(t0);
  char line[200];
  std::snprintf(line, sizeof line, "render: %dx%d, %lld pixels inside the hull, %lld no-data, %.3f s", options.width,
                options.height, local.inside_pixels, local.nodata_pixels, local.seconds_render);
  log(line);
  if (stats) *stats = local;
  return out;
}

}  // namespace ddt
