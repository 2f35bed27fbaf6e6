#include "image/cubic_surface.hpp"
#include "image/optimizer.hpp"
#include "image/rasterizer.hpp"
#include "test_support.hpp"
#include "image/triangulation.hpp"
#include "util/error.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>

using namespace ddt;

namespace {

// The initial value of pixels no triangle draws.
const float unwritten = std::numeric_limits<float>::quiet_NaN();

// Every pixel drawn exactly once: none left unwritten, and the pixels
// drawn (the image's minus uncovered) as many as the image has.
bool drawn_once(const Image& out, const RenderStats& st) {
  long long left = 0;
  for (std::size_t i = 0; i < out.pixels.size(); i += out.channels) left += std::isnan(out.pixels[i]);
  return left == 0 && st.uncovered == 0;
}

RenderGrid grid_for(int in_w, int in_h, int out_w, int out_h) {
  RenderGrid g;
  g.width = out_w;
  g.height = out_h;
  g.scale_x = double(out_w) / in_w;
  g.scale_y = double(out_h) / in_h;
  return g;
}

std::vector<float> random_values(std::size_t n, int C, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> v(n * C);
  for (auto& x : v) x = u(rng);
  return v;
}

// Nearest point of segment p-q to r.
Point2 nearest_on_segment(const Point2& p, const Point2& q, const Point2& r) {
  const double dx = q.x - p.x, dy = q.y - p.y;
  const double t = std::clamp(((r.x - p.x) * dx + (r.y - p.y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
  return {p.x + t * dx, p.y + t * dy};
}

// The triangles of a w x h grid of points numbered from `first`, row by
// row, each cell kept split by the same diagonal.
template <class Keep>
std::vector<std::array<index_t, 3>> cell_triangles(int w, int h, index_t first, Keep keep) {
  std::vector<std::array<index_t, 3>> tris;
  for (int y = 0; y + 1 < h; ++y)
    for (int x = 0; x + 1 < w; ++x) {
      if (!keep(x, y)) continue;
      const index_t i00 = first + y * w + x, i10 = i00 + 1, i01 = i00 + w, i11 = i01 + 1;
      tris.push_back({i00, i10, i01});
      tris.push_back({i10, i11, i01});
    }
  return tris;
}

// The 5x3 grid without the two middle cells of the top row: a U, whose
// notch makes rows through the arms meet the boundary four times.
Mesh2 u_shaped_grid() {
  return test::mesh_from_triangles(test::grid_points(5, 3),
                                   cell_triangles(5, 3, 0, [](int x, int y) { return !(y == 0 && (x == 1 || x == 2)); }));
}

}  // namespace

TEST_CASE("render_mesh: at scale 3, output (3i+1, 3j+1) equals input sample (i, j) exactly") {
  const int w = 9, h = 7, C = 3;
  Mesh2 m = delaunay_triangulation(test::grid_points(w, h));
  const std::vector<float> values = random_values(m.points.size(), C, 1);
  optimize_lawson(m, values, C, find_cost("sederberg"));  // thin triangles too
  const Image out = render_mesh(m, values, C, grid_for(w, h, 3 * w, 3 * h));
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      for (int c = 0; c < C; ++c) REQUIRE(out.at(3 * i + 1, 3 * j + 1, c) == values[(j * w + i) * C + c]);
}

TEST_CASE("render_mesh: a linear ramp is reproduced at any scale, and clamped outside the hull") {
  const int w = 11, h = 8;
  for (double angle : {0.0, 17.0, 45.0, 120.0, 250.0}) {
    const double gx = std::cos(angle * M_PI / 180), gy = std::sin(angle * M_PI / 180);
    auto ramp = [&](double x, double y) { return 0.5 + 0.05 * (gx * x + gy * y); };
    std::vector<float> values;
    for (const Point2& p : test::grid_points(w, h)) values.push_back(static_cast<float>(ramp(p.x, p.y)));
    Mesh2 m = delaunay_triangulation(test::grid_points(w, h));
    for (double scale : {1.0, 2.5, 3.0, 7.3, 10.0}) {
      CAPTURE(angle);
      CAPTURE(scale);
      const int ow = static_cast<int>(std::round(w * scale)), oh = static_cast<int>(std::round(h * scale));
      const RenderGrid g = grid_for(w, h, ow, oh);
      RenderStats st;
      const Image out = render_mesh(m, values, 1, g, &st, true, unwritten);
      CHECK(drawn_once(out, st));
      double worst = 0;
      for (int Y = 0; Y < oh; ++Y)
        for (int X = 0; X < ow; ++X) {
          // Inside the hull the ramp itself; outside, its value at the nearest hull point (a clamp on a grid).
          const double x = std::clamp((X + 0.5) / g.scale_x, 0.5, w - 0.5);
          const double y = std::clamp((Y + 0.5) / g.scale_y, 0.5, h - 0.5);
          worst = std::max(worst, std::abs(out.at(X, Y) - ramp(x, y)));
        }
      CHECK(worst < 2e-7);
    }
  }
}

TEST_CASE("render_mesh: every pixel is owned by exactly one triangle") {
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    Mesh2 m = delaunay_triangulation(test::random_points(200, seed, 16.0));
    const std::vector<float> values = random_values(m.points.size(), 1, seed);
    optimize_lawson(m, values, 1, find_cost("sederberg"));
    for (double scale : {1.0, 3.0, 6.7}) {
      RenderGrid g;
      g.width = g.height = static_cast<int>(16 * scale);
      g.scale_x = g.scale_y = scale;
      RenderStats st;
      CHECK(drawn_once(render_mesh(m, values, 1, g, &st, true, unwritten), st));
    }
  }
  // A grid at scale 4: many pixel centres lie exactly on edges and vertices.
  Mesh2 grid = delaunay_triangulation(test::grid_points(10, 10));
  const std::vector<float> values = random_values(100, 1, 5);
  optimize_lawson(grid, values, 1, find_cost("variance"));
  RenderStats st;
  CHECK(drawn_once(render_mesh(grid, values, 1, grid_for(10, 10, 40, 40), &st, true, unwritten), st));
}

TEST_CASE("render_mesh: outside the hull of scattered points, the nearest hull point's value") {
  Mesh2 m = delaunay_triangulation(test::random_points(80, 17, 10.0));
  const std::vector<float> values = random_values(m.points.size(), 1, 17);
  RenderGrid g;
  g.width = g.height = 50;
  g.scale_x = g.scale_y = 5;
  const Image out = render_mesh(m, values, 1, g);
  std::vector<index_t> hull;
  for (index_t e = 0; e < m.half_edge_count(); ++e)
    if (m.opp[e] == no_edge) hull.push_back(e);
  int outside = 0;
  for (int Y = 0; Y < g.height; Y += 3)
    for (int X = 0; X < g.width; X += 3) {
      const Point2 p{(X + 0.5) / 5, (Y + 0.5) / 5};
      double best = 1e300, value = 0;
      bool inside = true;
      for (index_t e : hull) {
        const index_t u = m.tri[e], v = m.tri[next_edge(e)];
        if (orientation(m.points[u], m.points[v], p) < 0) inside = false;
        const Point2 q = nearest_on_segment(m.points[u], m.points[v], p);
        const double d = std::hypot(q.x - p.x, q.y - p.y);
        if (d < best) {
          best = d;
          const double len = std::hypot(m.points[v].x - m.points[u].x, m.points[v].y - m.points[u].y);
          const double t = std::hypot(q.x - m.points[u].x, q.y - m.points[u].y) / len;
          value = (1 - t) * values[u] + t * values[v];
        }
      }
      if (inside) continue;
      ++outside;
      CHECK(out.at(X, Y) == doctest::Approx(value).epsilon(1e-5));
    }
  CHECK(outside > 20);
}

TEST_CASE("render_mesh cubic: every pixel in the hull is its triangle's Bezier patch, clamped to the vertex values") {
  // Pieces of 16 pixels or more take the power form, thin triangles from the
  // optimizer and small pieces the Bernstein form. Points on a 1/64 lattice
  // make every pixel coordinate exact at scales 2, 4 and 10 (the paired
  // Bernstein path); arbitrary points and x13.7 take the inexact one. Each
  // channel count has its own instantiation (1, 3, 4; others at run time).
  const std::vector<std::pair<int, bool>> cases = {{3, false}, {3, true}, {1, true}, {4, false}, {2, true}};
  for (const auto& [C, lattice] : cases) {
    CAPTURE(C);
    std::vector<Point2> points = test::random_points(60, 31, 10.0);
    if (lattice) {
      auto less = [](const Point2& a, const Point2& b) { return std::tie(a.x, a.y) < std::tie(b.x, b.y); };
      auto same = [](const Point2& a, const Point2& b) { return a.x == b.x && a.y == b.y; };
      for (Point2& p : points) p = {std::round(p.x * 64) / 64, std::round(p.y * 64) / 64};
      std::sort(points.begin(), points.end(), less);
      points.erase(std::unique(points.begin(), points.end(), same), points.end());
    }
    Mesh2 m = delaunay_triangulation(points);
    const std::vector<float> values = random_values(m.points.size(), C, 31);
    optimize_lawson(m, values, C, find_cost("sederberg"));
    std::vector<float> gradients = random_values(m.points.size(), 2 * C, 32);
    for (float& g : gradients) g = 0.6f * g - 0.3f;
    for (double scale : lattice ? std::vector<double>{2.0, 4.0, 10.0} : std::vector<double>{1.5, 4.0, 10.0, 13.7}) {
      CAPTURE(lattice);
      CAPTURE(scale);
      RenderGrid grid;
      grid.width = grid.height = static_cast<int>(10 * scale);
      grid.scale_x = grid.scale_y = scale;
      RenderStats stats;
      const Image out = render_mesh(m, values, C, grid, &stats, false, -1.0f, &gradients);
      if (scale >= 10) CHECK(stats.power_pieces > 0);
      if (scale < 2) CHECK(stats.power_pieces == 0);
      CHECK(stats.bernstein_pieces > 0);
      // A centre on an edge may go to either triangle (their clamp ranges
      // differ) or, on the hull, to none (the tie rule): the pixel must
      // match one of the triangles holding it, or be on an edge.
      double worst = 0;
      long long inside = 0;
      for (int Y = 0; Y < grid.height; ++Y)
        for (int X = 0; X < grid.width; ++X) {
          const Point2 q{(X + 0.5) / scale, (Y + 0.5) / scale};
          double best = std::numeric_limits<double>::infinity();
          bool on_edge = false;
          for (index_t t = 0; t < m.triangle_count(); ++t) {
            const index_t* v = &m.tri[3 * static_cast<std::size_t>(t)];
            const Point2 &p0 = m.points[v[0]], &p1 = m.points[v[1]], &p2 = m.points[v[2]];
            const double area2 = (p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x);
            const double l0 = ((p2.x - p1.x) * (q.y - p1.y) - (p2.y - p1.y) * (q.x - p1.x)) / area2;
            const double l1 = ((p0.x - p2.x) * (q.y - p2.y) - (p0.y - p2.y) * (q.x - p2.x)) / area2;
            const double l2 = 1 - l0 - l1;
            if (l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9) continue;
            on_edge |= std::min({l0, l1, l2}) < 1e-9;
            double error = 0;
            for (int c = 0; c < C; ++c) {
              auto z = [&](int k) { return double(values[static_cast<std::size_t>(v[k]) * C + c]); };
              auto g = [&](int k) { return &gradients[(static_cast<std::size_t>(v[k]) * C + c) * 2]; };
              const double g0[2] = {g(0)[0], g(0)[1]}, g1[2] = {g(1)[0], g(1)[1]}, g2[2] = {g(2)[0], g(2)[1]};
              const double patch = eval_cubic_patch(cubic_patch(p0, p1, p2, z(0), z(1), z(2), g0, g1, g2), l0, l1, l2);
              const double expected = std::clamp(patch, std::min({z(0), z(1), z(2)}), std::max({z(0), z(1), z(2)}));
              error = std::max(error, std::abs(out.at(X, Y, c) - expected));
            }
            best = std::min(best, error);
          }
          if (best == std::numeric_limits<double>::infinity()) continue;  // outside the hull
          ++inside;
          if (out.at(X, Y, 0) == -1.0f && on_edge) continue;  // on the hull, left to the outside
          worst = std::max(worst, best);
        }
      CHECK(inside > grid.width * grid.height / 2);
      CHECK(worst < 1e-6);
    }
  }
}

TEST_CASE("render_mesh: without the rim, outside pixels keep the no-data value") {
  Mesh2 m = delaunay_triangulation(test::random_points(50, 23, 10.0));
  const std::vector<float> values(m.points.size(), 0.5f);
  RenderGrid g;
  g.width = g.height = 20;
  g.scale_x = g.scale_y = 2;
  RenderStats st;
  const Image out = render_mesh(m, values, 1, g, &st, false, -1.0f);
  long long nodata = 0;
  for (float v : out.pixels) {
    CHECK((v == 0.5f || v == -1.0f));
    nodata += v == -1.0f;
  }
  CHECK(nodata == st.uncovered);  // the pixels drawn are the others, each once
  CHECK(nodata > 0);
}

TEST_CASE("render_mesh: a U-shaped mesh without the rim: rows crossing both arms, the notch left alone") {
  // Rows through the arms meet the boundary four times (two walks per row).
  const int w = 5, h = 3;
  const Mesh2 m = u_shaped_grid();
  REQUIRE(m.triangle_count() == 12);
  // A linear function is reproduced wherever the mesh is.
  auto f = [](double x, double y) { return 0.25 + 0.125 * x - 0.0625 * y; };
  std::vector<float> values;
  for (const Point2& p : m.points) values.push_back(static_cast<float>(f(p.x, p.y)));
  for (double scale : {4.0, 3.7}) {
    RenderGrid g;
    g.width = static_cast<int>(w * scale), g.height = static_cast<int>(h * scale);
    g.scale_x = g.scale_y = scale;
    RenderStats st;
    const Image out = render_mesh(m, values, 1, g, &st, false, -1.0f);
    long long nodata = 0, inside = 0;
    for (int Y = 0; Y < g.height; ++Y)
      for (int X = 0; X < g.width; ++X) {
        const double x = (X + 0.5) / scale, y = (Y + 0.5) / scale;  // input position
        const bool in_notch = x > 1.5 && x < 3.5 && y < 1.5;
        const bool in_mesh = x >= 0.5 && x <= 4.5 && y >= 0.5 && y <= 2.5 && !in_notch;
        const float v = out.at(X, Y, 0);
        nodata += v == -1.0f;
        if (in_notch) CHECK(v == -1.0f);
        if (in_mesh && x > 0.51 && x < 4.49 && y > 0.51 && y < 2.49 && !(x > 1.49 && x < 3.51 && y < 1.51)) {
          CHECK(v == doctest::Approx(f(x, y)).epsilon(1e-6));
          ++inside;
        }
      }
    CHECK(inside > 0);
    CHECK(st.uncovered == nodata);  // the pixels drawn are the others, each once
  }
}

TEST_CASE("render_mesh: collinear samples interpolate along their line") {
  // A single row: values 0, 1, 2, 3 at x = 0.5 .. 3.5.
  Mesh2 m = delaunay_triangulation(test::grid_points(4, 1));
  REQUIRE(m.triangle_count() == 0);
  const std::vector<float> values = {0, 1, 2, 3};
  const Image out = render_mesh(m, values, 1, grid_for(4, 1, 8, 3));
  for (int Y = 0; Y < 3; ++Y) {
    CHECK(out.at(0, Y) == 0.0f);                            // x = 0.25: clamped to 0.5
    CHECK(out.at(3, Y) == doctest::Approx(1.25));           // x = 1.75
    CHECK(out.at(7, Y) == 3.0f);                            // x = 3.75: clamped
  }
  Mesh2 single = delaunay_triangulation(test::grid_points(1, 1));
  const Image one = render_mesh(single, {0.25f}, 1, grid_for(1, 1, 5, 5));
  for (float v : one.pixels) CHECK(v == 0.25f);
}

namespace {

struct Sampling {
  double scale_x, scale_y, origin_x, origin_y;
  bool lattice;  // exact, every vertex at the same fractional position in output pixels
};

// Renders m with and without drawing by shape; requires the same bits and
// counts. Returns the triangles drawn by shape.
long long compare_shapes_with_walk(const Mesh2& m, int C, bool cubic, const Sampling& k, bool fill_outside,
                                   bool window) {
  const std::vector<float> values = random_values(m.points.size(), C, 11);
  std::vector<float> gradients = random_values(m.points.size(), 2 * C, 12);
  for (float& g : gradients) g -= 0.5f;
  double w = 0, h = 0;
  for (const Point2& p : m.points) w = std::max(w, p.x + 0.5), h = std::max(h, p.y + 0.5);
  RenderGrid g;
  g.width = static_cast<int>(w * k.scale_x), g.height = static_cast<int>(h * k.scale_y);
  g.scale_x = k.scale_x, g.scale_y = k.scale_y;
  g.origin_x = k.origin_x, g.origin_y = k.origin_y;
  int out_row = 0;
  if (window) g.first_row = 5, g.rows = g.height / 2, out_row = 2;
  const int rows = window ? g.rows : g.height;
  Image by_shape(g.width, rows + out_row, C, -1.0f), walked = by_shape;
  RenderStats shape_stats, walk_stats;
  render_mesh_into(by_shape, out_row, m, values, C, g, &shape_stats, fill_outside, cubic ? &gradients : nullptr);
  g.by_shapes = false;
  render_mesh_into(walked, out_row, m, values, C, g, &walk_stats, fill_outside, cubic ? &gradients : nullptr);
  CHECK(walk_stats.shaped_triangles == 0);
  REQUIRE(by_shape.pixels.size() == walked.pixels.size());
  CHECK(std::memcmp(by_shape.pixels.data(), walked.pixels.data(), by_shape.pixels.size() * sizeof(float)) == 0);
  CHECK(shape_stats.uncovered == walk_stats.uncovered);
  CHECK(shape_stats.power_pieces == walk_stats.power_pieces);
  CHECK(shape_stats.bernstein_pieces == walk_stats.bernstein_pieces);
  return shape_stats.shaped_triangles;
}

}  // namespace

TEST_CASE("render_mesh: a lattice mesh drawn by shape equals the walked one, bit for bit") {
  // An optimized grid (thin triangles of many shapes); a grid with a hole
  // (long triangles across it: at x10 offsets beyond the shape table's,
  // drawn from their rows); and a random third of the lattice (shapes too
  // varied to pay: walked, which this only checks gives the same bits).
  const int w = 23, h = 17;
  std::vector<Mesh2> meshes;
  std::mt19937 rng(7);
  {
    Mesh2 m = delaunay_triangulation(test::grid_points(w, h));
    std::vector<float> edge;  // a slanted step with noise: flips along it
    std::uniform_real_distribution<float> noise(0.0f, 0.1f);
    for (const Point2& p : m.points) edge.push_back((p.x + 0.4 * p.y > 12 ? 0.8f : 0.2f) + noise(rng));
    optimize_lawson(m, edge, 1, find_cost("sederberg"));
    meshes.push_back(std::move(m));
    std::vector<Point2> holed;
    for (const Point2& p : test::grid_points(w, h))
      if (!(p.x > 6 && p.x < 15 && p.y > 5 && p.y < 12)) holed.push_back(p);
    meshes.push_back(delaunay_triangulation(holed));
    std::vector<Point2> subset;
    for (const Point2& p : test::grid_points(w, h))
      if (rng() % 3 == 0) subset.push_back(p);
    meshes.push_back(delaunay_triangulation(subset));
  }
  // Origins 2 and -1.5 put the mesh off the image; unequal scales and
  // phases in x and y; the last two are not lattices in output pixels.
  const Sampling cases[] = {{1, 1, 0, 0, true},      {2, 2, 0, 0, true},      {3, 3, 0, 0, true},
                            {4, 4, 0, 0, true},      {6, 6, 0, 0, true},      {10, 10, 0, 0, true},
                            {4, 4, 0.25, 0.25, true}, {4, 4, 2, 2, true},      {3, 3, -1.5, -1.5, true},
                            {2, 3, 0, 0, true},      {4, 1, 0.25, -0.5, true}, {5, 3, 0.1, 0.75, true},
                            {2.5, 2.5, 0, 0, false}, {4, 4, 0.3, 0.3, false}};
  int expected = 0;
  for (std::size_t mi = 0; mi < meshes.size(); ++mi)
    for (int C : {1, 2, 3, 4})
      for (bool cubic : {false, true})
        for (const Sampling& k : cases)
          for (bool fill_outside : {true, false})
            for (bool window : {false, true}) {
              CAPTURE(mi);
              CAPTURE(C);
              CAPTURE(cubic);
              CAPTURE(k.scale_x);
              CAPTURE(k.scale_y);
              CAPTURE(k.origin_x);
              CAPTURE(k.origin_y);
              CAPTURE(fill_outside);
              CAPTURE(window);
              const long long shaped = compare_shapes_with_walk(meshes[mi], C, cubic, k, fill_outside, window);
              if (mi == 2) continue;
              const bool expect_shapes = k.lattice && k.scale_x * k.scale_y <= (cubic ? 36 : 100);
              CHECK((shaped > 0) == expect_shapes);
              expected += expect_shapes;
            }
  CHECK(expected > 100);
}

TEST_CASE("render_mesh: drawn by shape, several chunks of triangles, a notched hull, unused vertices") {
  // 90x60 grid: about 10 600 triangles, chunks of 4096 drawn in parallel.
  {
    Mesh2 m = delaunay_triangulation(test::grid_points(90, 60));
    const std::vector<float> field = random_values(m.points.size(), 1, 3);
    optimize_lawson(m, field, 1, find_cost("sederberg"));
    for (bool cubic : {false, true})
      for (double scale : {2.0, 4.0}) {
        CAPTURE(cubic);
        CAPTURE(scale);
        CHECK(compare_shapes_with_walk(m, 3, cubic, {scale, scale, 0, 0, true}, true, false) > 4096);
      }
  }
  // The U-shaped grid: with the rim its slabs reach over the other arm, so
  // only the walk draws it; without the rim shapes do.
  {
    const Mesh2 m = u_shaped_grid();
    for (bool cubic : {false, true}) {
      CAPTURE(cubic);
      CHECK(compare_shapes_with_walk(m, 1, cubic, {4, 4, 0, 0, true}, true, false) == 0);
      CHECK(compare_shapes_with_walk(m, 1, cubic, {4, 4, 0, 0, true}, false, false) > 0);
    }
  }
  // An unused vertex: on the lattice it changes nothing, off it (here
  // vertex 0, whose phase the others are compared with) shapes are off.
  for (const Point2 extra : {Point2{7.5, 1.5}, Point2{7.25, 1.5}}) {
    std::vector<Point2> points = {extra};
    for (const Point2& p : test::grid_points(6, 4)) points.push_back(p);
    const Mesh2 m = test::mesh_from_triangles(points, cell_triangles(6, 4, 1, [](int, int) { return true; }));
    CAPTURE(extra.x);
    CHECK((compare_shapes_with_walk(m, 3, false, {3, 3, 0, 0, true}, true, false) > 0) == (extra.x == 7.5));
  }
}

TEST_CASE("add_mesh_render_into: the same bits as drawing into an image of its own and adding it") {
  // Lattice meshes drawn by shape (at x3 their vertices fall on pixel
  // centres, written exactly), a non-lattice mesh (walked), a hull that is
  // not convex (the rim can reach over it), and collinear points.
  std::vector<Mesh2> meshes;
  std::mt19937 rng(11);
  {
    Mesh2 m = delaunay_triangulation(test::grid_points(19, 13));
    const std::vector<float> field = random_values(m.points.size(), 1, 5);
    optimize_lawson(m, field, 1, find_cost("sederberg"));
    meshes.push_back(std::move(m));
    std::vector<Point2> scattered;
    std::uniform_real_distribution<double> u(0.0, 12.0);
    for (int i = 0; i < 60; ++i) scattered.push_back({u(rng) * 1.5, u(rng)});
    meshes.push_back(delaunay_triangulation(scattered));
    meshes.push_back(u_shaped_grid());
    meshes.push_back(delaunay_triangulation({{0.5, 0.5}, {2.5, 1.5}, {4.5, 2.5}}));
  }
  for (std::size_t mi = 0; mi < meshes.size(); ++mi)
    for (int C : {1, 3})
      for (double scale : {3.0, 4.0, 2.5})
        for (bool window : {false, true}) {
          CAPTURE(mi);
          CAPTURE(C);
          CAPTURE(scale);
          CAPTURE(window);
          const Mesh2& m = meshes[mi];
          const std::vector<float> values = random_values(m.points.size(), C, 17 + static_cast<unsigned>(mi));
          RenderGrid g = grid_for(20, 14, static_cast<int>(20 * scale), static_cast<int>(14 * scale));
          if (window) g.first_row = 7, g.rows = 13;
          const int rows = window ? g.rows : g.height, out_row = window ? 2 : 0;
          Image base(g.width, rows + out_row + 1, C);
          base.pixels = random_values(base.pixel_count(), C, 23);
          const Image drawn = render_mesh(m, values, C, g);
          Image expected = base;
          for (int y = 0; y < rows; ++y)
            for (int x = 0; x < g.width; ++x)
              for (int c = 0; c < C; ++c) expected.at(x, y + out_row, c) += drawn.at(x, y, c);
          Image added = base;
          add_mesh_render_into(added, out_row, m, values, C, g);
          CHECK(std::memcmp(added.pixels.data(), expected.pixels.data(), added.pixels.size() * sizeof(float)) == 0);
        }
}

TEST_CASE("RenderPlan: windows of rows drawn through one plan equal the whole render, bit for bit") {
  // An optimized lattice grid of several chunks of triangles (drawn by
  // shape at x3 and x4, walked at x2.5 and x7, where the cubic's pieces
  // take both forms), scattered points (walked), a hull that is not convex
  // and collinear points; linear, cubic and added renders; windows of 1 to
  // 40 rows cut where window_boundary() says, the channels changing
  // between calls (the plan's shape tables are per channel count).
  std::vector<Mesh2> meshes;
  std::mt19937 rng(5);
  {
    Mesh2 m = delaunay_triangulation(test::grid_points(90, 50));
    const std::vector<float> field = random_values(m.points.size(), 1, 9);
    optimize_lawson(m, field, 1, find_cost("sederberg"));
    meshes.push_back(std::move(m));
    std::vector<Point2> scattered;
    std::uniform_real_distribution<double> u(0.0, 49.0);
    for (int i = 0; i < 400; ++i) scattered.push_back({u(rng) * 1.8, u(rng)});
    meshes.push_back(delaunay_triangulation(scattered));
    meshes.push_back(u_shaped_grid());
    meshes.push_back(delaunay_triangulation({{0.5, 0.5}, {20.5, 10.5}, {40.5, 20.5}}));
  }
  for (std::size_t mi = 0; mi < meshes.size(); ++mi)
    for (double scale : {3.0, 4.0, 2.5, 7.0}) {
      const Mesh2& m = meshes[mi];
      const RenderGrid g = grid_for(90, 50, static_cast<int>(90 * scale), static_cast<int>(50 * scale));
      const RenderPlan plan(m, g);
      for (int mode = 0; mode < 3; ++mode)  // linear, cubic, added
        for (int C : {3, 1}) {
          CAPTURE(mi);
          CAPTURE(scale);
          CAPTURE(mode);
          CAPTURE(C);
          const std::vector<float> values = random_values(m.points.size(), C, 31 + static_cast<unsigned>(mi));
          std::vector<float> gradients = random_values(m.points.size(), 2 * C, 37);
          for (float& v : gradients) v -= 0.5f;
          const std::vector<float>* cubic = mode == 1 ? &gradients : nullptr;
          Image base(g.width, g.height, C);
          base.pixels = random_values(base.pixel_count(), C, 41);
          Image whole = base;
          if (mode == 2)
            add_mesh_render_into(whole, 0, m, values, C, g);
          else
            render_mesh_into(whole, 0, m, values, C, g, nullptr, true, cubic);
          Image windows = base;
          std::uniform_int_distribution<int> height(1, 40);
          int drawn_rows = 0;
          for (int first = 0; first < g.height;) {
            const int rows = plan.window_boundary(first + height(rng)) - first;
            REQUIRE(rows > 0);
            Image part(g.width, rows + 1, C);  // drawn at row 1 of an image of its own
            std::copy_n(&base.pixels[base.index(0, first)], static_cast<std::size_t>(g.width) * C * rows, &part.pixels[part.index(0, 1)]);
            RenderStats stats;
            if (mode == 2)
              add_mesh_render_into(part, 1, plan, values, C, first, rows, &stats);
            else
              render_mesh_into(part, 1, plan, values, C, first, rows, &stats, cubic);
            if (mi != 2) CHECK(stats.uncovered == 0);  // the U's rim reaches over its other arm
            std::copy_n(&part.pixels[part.index(0, 1)], static_cast<std::size_t>(g.width) * C * rows, &windows.pixels[windows.index(0, first)]);
            first += rows, drawn_rows += rows;
          }
          CHECK(drawn_rows == g.height);
          CHECK(plan.window_boundary(g.height + 5) == g.height);
          CHECK(std::memcmp(windows.pixels.data(), whole.pixels.data(), whole.pixels.size() * sizeof(float)) == 0);
        }
    }
}

TEST_CASE("RenderPlan: refuses what it cannot draw") {
  const Mesh2 m = delaunay_triangulation(test::grid_points(6, 5));
  const RenderGrid g = grid_for(6, 5, 18, 15);
  const std::vector<float> values = random_values(m.points.size(), 1, 3);
  Image out(18, 15, 1);
  const RenderPlan no_rim(m, g, false);
  CHECK_THROWS_AS(add_mesh_render_into(out, 0, no_rim, values, 1, 0, 15), Error);
  const RenderPlan plan(m, g);
  CHECK_THROWS_AS(render_mesh_into(out, 0, plan, std::vector<float>(values.begin(), values.end() - 1), 1, 0, 15),
                  Error);
  CHECK_THROWS_AS(render_mesh_into(out, 4, plan, values, 1, 0, 15), Error);  // rows beyond the image
  CHECK_NOTHROW(render_mesh_into(out, 4, plan, values, 1, 3, 11));
}

TEST_CASE("add_mesh_render_into and the cubic render_mesh_into: windows of rows of values or gradients draw the whole bits, and a vertex beyond them is refused") {
  // An optimized lattice (vertex y * W + x): long triangles, rows of
  // vertices a window of output rows reaches found from the mesh itself.
  const int W = 60, H = 40;
  Mesh2 m = delaunay_triangulation(test::grid_points(W, H));
  optimize_lawson(m, random_values(m.points.size(), 1, 12), 1, find_cost("sederberg"));
  int span = 0;  // the most rows a triangle spans
  for (std::size_t t = 0; 3 * t < m.tri.size(); ++t) {
    int lo = H, hi = 0;
    for (int i = 0; i < 3; ++i) {
      const int row = static_cast<int>(m.tri[3 * t + i]) / W;
      lo = std::min(lo, row), hi = std::max(hi, row);
    }
    span = std::max(span, hi - lo);
  }
  REQUIRE(span > 1);
  for (double scale : {3.0, 2.5}) {
    CAPTURE(scale);
    const int C = 3;
    const RenderGrid g = grid_for(W, H, static_cast<int>(W * scale), static_cast<int>(H * scale));
    const RenderPlan plan(m, g);
    const std::vector<float> values = random_values(m.points.size(), C, 17);
    Image whole(g.width, g.height, C);
    whole.pixels = random_values(whole.pixel_count(), C, 19);
    Image windows = whole;
    add_mesh_render_into(whole, 0, m, values, C, g);
    // The vertex rows a window of output rows [first, end) reads: around the
    // input rows its samples (at (Y + 0.5) / scale, vertices at row + 0.5) fall in.
    auto vertex_rows = [&](int first, int end) {
      const int top = static_cast<int>(std::floor((first + 0.5) / scale - 0.5)) - span - 1;
      const int bottom = static_cast<int>(std::ceil((end - 0.5) / scale - 0.5)) + span + 2;
      return std::pair{std::clamp(top, 0, H), std::clamp(bottom, 0, H)};
    };
    // The cubic surface from windows of gradients (2 C a vertex).
    std::vector<float> gradients = random_values(m.points.size(), 2 * C, 23);
    for (float& v : gradients) v -= 0.5f;
    const Image cubic_whole = render_mesh(m, values, C, g, nullptr, true, 0.0f, &gradients);
    Image cubic_windows(g.width, g.height, C);
    for (int first = 0; first < g.height;) {
      const int rows = plan.window_boundary(first + 7) - first;
      const auto [top, bottom] = vertex_rows(first, first + rows);
      // Only the window's values (gradients), in a buffer of their own.
      const std::vector<float> held(values.begin() + static_cast<std::ptrdiff_t>(top) * W * C,
                                    values.begin() + static_cast<std::ptrdiff_t>(bottom) * W * C);
      add_mesh_render_into(windows, first, plan, VertexValues{held.data(), index_t(top) * W, index_t(bottom) * W}, C,
                           first, rows);
      const std::vector<float> held_gradients(gradients.begin() + static_cast<std::ptrdiff_t>(top) * W * 2 * C,
                                              gradients.begin() + static_cast<std::ptrdiff_t>(bottom) * W * 2 * C);
      render_mesh_into(cubic_windows, first, plan, values, C, first, rows,
                       VertexValues{held_gradients.data(), index_t(top) * W, index_t(bottom) * W});
      first += rows;
    }
    CHECK(std::memcmp(windows.pixels.data(), whole.pixels.data(), whole.pixels.size() * sizeof(float)) == 0);
    CHECK(std::memcmp(cubic_windows.pixels.data(), cubic_whole.pixels.data(), cubic_whole.pixels.size() * sizeof(float)) ==
          0);
    // A window in the middle without the row of vertices at or above its first samples.
    const int first = plan.window_boundary(g.height / 2);
    const int needed = static_cast<int>(std::floor((first + 0.5) / scale - 0.5));
    const auto [top, bottom] = vertex_rows(first, first + 4);
    REQUIRE(needed >= top);
    const std::vector<float> short_of_one(values.begin() + static_cast<std::ptrdiff_t>(needed + 1) * W * C,
                                          values.begin() + static_cast<std::ptrdiff_t>(bottom) * W * C);
    Image out(g.width, 4, C);
    CHECK_THROWS_AS(add_mesh_render_into(out, 0, plan,
                                         VertexValues{short_of_one.data(), index_t(needed + 1) * W, index_t(bottom) * W},
                                         C, first, 4),
                    Error);
    const std::vector<float> gradients_short_of_one(
        gradients.begin() + static_cast<std::ptrdiff_t>(needed + 1) * W * 2 * C,
        gradients.begin() + static_cast<std::ptrdiff_t>(bottom) * W * 2 * C);
    CHECK_THROWS_AS(render_mesh_into(out, 0, plan, values, C, first, 4,
                                     VertexValues{gradients_short_of_one.data(), index_t(needed + 1) * W,
                                                  index_t(bottom) * W}),
                    Error);
    // The top rows' rim patches need the first rows' gradients.
    CHECK_THROWS_AS(render_mesh_into(out, 0, plan, values, C, 0, 4,
                                     VertexValues{gradients_short_of_one.data(), index_t(needed + 1) * W,
                                                  index_t(bottom) * W}),
                    Error);
  }
  // A window of values draws only an added surface on a convex hull.
  const Mesh2 notched = u_shaped_grid();
  const RenderGrid g = grid_for(5, 3, 10, 6);
  const std::vector<float> values = random_values(notched.points.size(), 1, 3);
  Image out(10, 6, 1);
  const VertexValues all{values.data(), 0, index_t(notched.points.size())};
  CHECK_THROWS_AS(add_mesh_render_into(out, 0, RenderPlan(notched, g), all, 1, 0, 6), Error);
}
