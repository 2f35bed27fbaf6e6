#include "rasterizer.hpp"

#include "cubic_surface.hpp"
#include "error.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace ddt {
namespace {

constexpr int band_rows = 32;
constexpr int max_channels = 16;

// Side of p relative to the directed line u->v with the exact predicate and
// the (eps, eps^2) perturbation of p on ties: +1 left, -1 right, never 0.
// Antisymmetric in (u, v), so two triangles sharing an edge never both own
// a point on it.
int tie_side(const Point2& u, const Point2& v) {
  // d/dx of the orientation determinant is (u.y - v.y), d/dy is (v.x - u.x).
  if (u.y != v.y) return u.y > v.y ? 1 : -1;
  return v.x > u.x ? 1 : -1;
}

// The surface to draw: the mesh's triangles, then the rim's (slabs and
// fans outside the hull). Vertex ids below V are the mesh's; id V + i is
// rim vertex i, which carries the value (and gradient) of mesh vertex
// rim_source[i].
struct Scene {
  const Mesh2& mesh;
  const std::vector<float>& values;
  int C;
  const RenderGrid& grid;
  const std::vector<float>* gradients = nullptr;  // cubic mode
  index_t V = 0, T = 0;
  std::vector<Point2> rim_points;  // input coordinates
  std::vector<index_t> rim_source;
  std::vector<index_t> rim_tris;   // counter-clockwise triples
  // Cubic mode: the Bézier control values of each rim triangle, C each.
  std::vector<std::array<double, 10>> rim_patches;
  // Exactness: when every drawn coordinate is a multiple of 2^-10 below 2^15
  // in magnitude (and pixel centres are integers below 2^15), edge functions
  // at pixel centres are exact in double: differences are multiples of
  // 2^-10 below 2^16 (26 bits), products multiples of 2^-20 below 2^32
  // (52 bits), their difference below 2^33 (53 bits). Integer scales and
  // most others (2.5, 0.75, ...) qualify; the rest take a filtered path.
  bool mesh_exact = false;
  std::vector<char> rim_exact;

  index_t triangle_count() const { return T + static_cast<index_t>(rim_tris.size() / 3); }
  void corners(index_t t, index_t out[3]) const {
    const index_t* src = t < T ? &mesh.tri[3 * static_cast<std::size_t>(t)] : &rim_tris[3 * static_cast<std::size_t>(t - T)];
    out[0] = src[0], out[1] = src[1], out[2] = src[2];
  }
  const Point2& input_point(index_t v) const { return v < V ? mesh.points[v] : rim_points[v - V]; }
  // Output pixel space: pixel centres at integers.
  Point2 pos(index_t v) const {
    const Point2& p = input_point(v);
    return {(p.x - grid.origin_x) * grid.scale_x - 0.5, (p.y - grid.origin_y) * grid.scale_y - 0.5};
  }
  index_t source(index_t v) const { return v < V ? v : rim_source[v - V]; }
  const float* value(index_t v) const { return &values[static_cast<std::size_t>(source(v)) * C]; }
  bool exact(index_t v) const { return v < V ? mesh_exact : rim_exact[v - V] != 0; }
};

bool exact_coordinate(double c) {
  return std::abs(c) < 32768.0 && c * 1024.0 == std::floor(c * 1024.0);
}

// Adds the slabs and corner fans that extend the hull's values outward.
// Built in input coordinates (distances there define "nearest"), far enough
// that the output domain is covered.
void add_rim(Scene& scene) {
  const Mesh2& mesh = scene.mesh;
  const RenderGrid& grid = scene.grid;
  const std::vector<float>& values = scene.values;
  const int C = scene.C;
  const index_t n_half = mesh.half_edge_count();
  std::vector<index_t> hull;
  for (index_t e = 0; e < n_half; ++e)
    if (mesh.opp[e] == no_edge) hull.push_back(e);
  if (hull.empty()) return;
  std::vector<std::pair<index_t, index_t>> outgoing;  // (hull vertex, its hull half-edge), sorted
  outgoing.reserve(hull.size());
  for (index_t e : hull) outgoing.emplace_back(mesh.tri[e], e);
  std::sort(outgoing.begin(), outgoing.end());
  auto outgoing_of = [&](index_t v) {
    return std::lower_bound(outgoing.begin(), outgoing.end(), std::make_pair(v, index_t(-1)))->second;
  };
  double lo_x = grid.origin_x, hi_x = grid.origin_x + grid.width / grid.scale_x;
  double lo_y = grid.origin_y, hi_y = grid.origin_y + grid.height / grid.scale_y;
  for (const Point2& p : mesh.points) {
    lo_x = std::min(lo_x, p.x), hi_x = std::max(hi_x, p.x);
    lo_y = std::min(lo_y, p.y), hi_y = std::max(hi_y, p.y);
  }
  const double far = 2.0 * std::hypot(hi_x - lo_x, hi_y - lo_y) + 1.0;

  auto add_vertex = [&](const Point2& p, index_t value_of) {
    scene.rim_points.push_back(p);
    scene.rim_source.push_back(value_of);
    return static_cast<index_t>(scene.V + scene.rim_points.size() - 1);
  };
  auto add_triangle = [&](index_t a, index_t b, index_t c) { scene.rim_tris.insert(scene.rim_tris.end(), {a, b, c}); };
  auto normal_of = [&](index_t e) {
    const Point2& u = mesh.points[mesh.tri[e]];
    const Point2& v = mesh.points[mesh.tri[next_edge(e)]];
    const double len = std::hypot(v.x - u.x, v.y - u.y);
    return Point2{(v.y - u.y) / len, -(v.x - u.x) / len};  // right of u->v: outside
  };
  // far_start[k], far_end[k]: the outer corners of hull edge k's slab, shared with the fans.
  std::vector<index_t> far_start(hull.size()), far_end(hull.size());
  std::vector<std::pair<index_t, std::size_t>> hull_index;  // (half-edge, k), sorted
  for (std::size_t k = 0; k < hull.size(); ++k) hull_index.emplace_back(hull[k], k);
  std::sort(hull_index.begin(), hull_index.end());
  auto index_of = [&](index_t e) {
    return std::lower_bound(hull_index.begin(), hull_index.end(), std::make_pair(e, std::size_t(0)))->second;
  };
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const index_t e = hull[k];
    const index_t u = mesh.tri[e], v = mesh.tri[next_edge(e)];
    const Point2 n = normal_of(e);
    const Point2 &pu = mesh.points[u], &pv = mesh.points[v];
    far_start[k] = add_vertex({pu.x + far * n.x, pu.y + far * n.y}, u);
    far_end[k] = add_vertex({pv.x + far * n.x, pv.y + far * n.y}, v);
    add_triangle(v, u, far_start[k]);
    add_triangle(v, far_start[k], far_end[k]);
    if (scene.gradients) {
      // The slab's value is the hull edge's cubic at the nearest edge point,
      // a function of t, the position along u->v. In (v, u, Fu), t = l0; in
      // (v, Fu, Fv), t = l0 + l2. A Bézier triangle of a function of
      // l0 (+ l2) has control value d[i] (d[i + k]) at index ijk.
      for (int pass = 0; pass < 2; ++pass)
        for (int c = 0; c < C; ++c) {
          const float* gu = &(*scene.gradients)[(static_cast<std::size_t>(u) * C + c) * 2];
          const float* gv = &(*scene.gradients)[(static_cast<std::size_t>(v) * C + c) * 2];
          const double dx = pv.x - pu.x, dy = pv.y - pu.y;
          const double zu = values[static_cast<std::size_t>(u) * C + c], zv = values[static_cast<std::size_t>(v) * C + c];
          const double d[4] = {zu, zu + (gu[0] * dx + gu[1] * dy) / 3, zv - (gv[0] * dx + gv[1] * dy) / 3, zv};
          // order: 300, 030, 003, 210, 120, 021, 012, 102, 201, 111 as (i, k) of l0, l2 powers
          const int ik[10][2] = {{3, 0}, {0, 0}, {0, 3}, {2, 0}, {1, 0}, {0, 1}, {0, 2}, {1, 2}, {2, 1}, {1, 1}};
          std::array<double, 10> b;
          for (int q = 0; q < 10; ++q) b[q] = d[pass == 0 ? ik[q][0] : ik[q][0] + ik[q][1]];
          scene.rim_patches.push_back(b);
        }
    }
  }
  const double max_piece = M_PI / 3;  // keeps each fan triangle's far side beyond `far` * cos(30deg)
  for (std::size_t k_in = 0; k_in < hull.size(); ++k_in) {
    const index_t e_in = hull[k_in];
    const index_t v = mesh.tri[next_edge(e_in)];
    const index_t e_out = outgoing_of(v);
    const std::size_t k_out = index_of(e_out);
    const Point2 n_in = normal_of(e_in), n_out = normal_of(e_out);
    const double turn = std::atan2(n_in.x * n_out.y - n_in.y * n_out.x, n_in.x * n_out.x + n_in.y * n_out.y);
    if (!(turn > 0)) continue;  // collinear hull vertex: slabs already meet
    const int pieces = static_cast<int>(std::ceil(turn / max_piece));
    const Point2& pv = mesh.points[v];
    index_t previous = far_end[k_in];
    for (int k = 1; k <= pieces; ++k) {
      index_t next_far = far_start[k_out];
      if (k < pieces) {
        const double a = turn * k / pieces, ca = std::cos(a), sa = std::sin(a);
        const Point2 dir{n_in.x * ca - n_in.y * sa, n_in.x * sa + n_in.y * ca};
        next_far = add_vertex({pv.x + far * dir.x, pv.y + far * dir.y}, v);
      }
      add_triangle(v, previous, next_far);
      if (scene.gradients)
        for (int c = 0; c < C; ++c) {
          std::array<double, 10> b;
          b.fill(values[static_cast<std::size_t>(v) * C + c]);
          scene.rim_patches.push_back(b);
        }
      previous = next_far;
    }
  }
}

// The cubic patch of scene triangle t (corners i) for channel c.
std::array<double, 10> scene_patch(const Scene& scene, index_t t, const index_t i[3], int c) {
  const int C = scene.C;
  if (t >= scene.T) return scene.rim_patches[static_cast<std::size_t>(t - scene.T) * C + c];
  const auto& P = scene.mesh.points;
  const auto& G = *scene.gradients;
  auto grad = [&](index_t v) { return &G[(static_cast<std::size_t>(v) * C + c) * 2]; };
  double g0[2] = {grad(i[0])[0], grad(i[0])[1]}, g1[2] = {grad(i[1])[0], grad(i[1])[1]},
         g2[2] = {grad(i[2])[0], grad(i[2])[1]};
  return cubic_patch(P[i[0]], P[i[1]], P[i[2]], scene.values[static_cast<std::size_t>(i[0]) * C + c],
                     scene.values[static_cast<std::size_t>(i[1]) * C + c],
                     scene.values[static_cast<std::size_t>(i[2]) * C + c], g0, g1, g2);
}

// One directed edge u->v of a triangle: inside is its left (side > 0).
struct Edge {
  Point2 u, v;
  double alpha, beta;  // v - u
  int tie;             // side on the line
  bool exact;          // plain double evaluation is exact
  // Side of pixel centre (X, Y): +1 or -1.
  int side(double X, double Y) const {
    const double l = alpha * (Y - u.y), r = beta * (X - u.x);
    const double e = l - r;
    if (exact) return e > 0 ? 1 : e < 0 ? -1 : tie;
    // Shewchuk's orient2d error bound, rounded up: beyond it the sign is
    // right; within, CGAL's exact predicate decides.
    if (std::abs(e) > 1e-15 * (std::abs(l) + std::abs(r))) return e > 0 ? 1 : -1;
    const int s = orientation(u, v, Point2{X, Y});
    return s != 0 ? s : tie;
  }
};

// Per-band scratch: coverage counts of the band's pixels.
struct BandState {
  std::vector<unsigned char> hits;
};

// Draws the part of triangle t on grid rows [row_begin, row_end) into `out`,
// whose row 0 is grid row row0; hits counts the band's pixels.
template <int CT>
void draw_triangle(const Scene& scene, index_t t, int row_begin, int row_end, int row0, Image& out,
                   unsigned char* hits) {
  const int C = CT > 0 ? CT : scene.C;
  index_t id[3];
  scene.corners(t, id);
  const Point2 p0 = scene.pos(id[0]), p1 = scene.pos(id[1]), p2 = scene.pos(id[2]);
  const bool exact = scene.exact(id[0]) && scene.exact(id[1]) && scene.exact(id[2]);
  {  // collapsed by the output transform: nothing to own
    const double d = (p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x);
    if (exact ? !(d > 0) : orientation(p0, p1, p2) <= 0) return;
  }
  const double min_y = std::min({p0.y, p1.y, p2.y}), max_y = std::max({p0.y, p1.y, p2.y});
  const double min_x = std::min({p0.x, p1.x, p2.x}), max_x = std::max({p0.x, p1.x, p2.x});
  const int y_lo = std::max(row_begin, static_cast<int>(std::ceil(min_y)));
  const int y_hi = std::min(row_end - 1, static_cast<int>(std::floor(max_y)));
  if (y_lo > y_hi) return;
  const int W = out.width;
  const int x_min = std::max(0, static_cast<int>(std::ceil(min_x)));
  const int x_max = std::min(W - 1, static_cast<int>(std::floor(max_x)));
  if (x_min > x_max) return;

  const Edge edges[3] = {
      {p0, p1, p1.x - p0.x, p1.y - p0.y, tie_side(p0, p1), exact},
      {p1, p2, p2.x - p1.x, p2.y - p1.y, tie_side(p1, p2), exact},
      {p2, p0, p0.x - p2.x, p0.y - p2.y, tie_side(p2, p0), exact},
  };
  double slope[3];  // dX/dY along each non-horizontal edge
  for (int k = 0; k < 3; ++k) slope[k] = edges[k].beta != 0 ? edges[k].alpha / edges[k].beta : 0;

  // Barycentric weights of p1 and p2: lambda1 = E20(p) / d1, lambda2 =
  // E01(p) / d2 (the edge functions of p2->p0 and p0->p1).
  const double ax = p0.x - p2.x, ay = p0.y - p2.y;
  const double bx = p1.x - p0.x, by = p1.y - p0.y;
  const double d1 = ax * (p1.y - p2.y) - ay * (p1.x - p2.x);
  const double d2 = bx * (p2.y - p0.y) - by * (p2.x - p0.x);
  const double inv1 = 1.0 / d1, inv2 = 1.0 / d2;
  const float *z0 = scene.value(id[0]), *z1 = scene.value(id[1]), *z2 = scene.value(id[2]);
  const bool cubic = scene.gradients != nullptr;
  // Linear: value = v0 + (X - p0.x) sx + (Y - p0.y) sy, the plane through
  // the three vertex values (exact at p0; the other vertices are written
  // exactly afterwards, see render_mesh).
  double v0[max_channels], sx[max_channels], sy[max_channels];
  // Cubic: Bézier control values, the middle ones pre-scaled by 3 and 6,
  // and the clamp to the vertex values (no overshoot, so no ringing beside
  // edges, whatever the gradients say).
  double b[max_channels][10], lo[max_channels], hi[max_channels];
  for (int c = 0; c < C; ++c) {
    const double dv1 = double(z1[c]) - z0[c], dv2 = double(z2[c]) - z0[c];
    v0[c] = z0[c];
    sx[c] = -ay * inv1 * dv1 - by * inv2 * dv2;
    sy[c] = ax * inv1 * dv1 + bx * inv2 * dv2;
    if (cubic) {
      const std::array<double, 10> patch = scene_patch(scene, t, id, c);
      for (int q = 0; q < 10; ++q) b[c][q] = patch[q] * (q < 3 ? 1.0 : q < 9 ? 3.0 : 6.0);
      lo[c] = std::min({double(z0[c]), double(z1[c]), double(z2[c])});
      hi[c] = std::max({double(z0[c]), double(z1[c]), double(z2[c])});
    }
  }

  for (int y = y_lo; y <= y_hi; ++y) {
    const double Y = y;
    int xs = x_min, xe = x_max;
    for (int k = 0; k < 3 && xs <= xe; ++k) {
      const Edge& ed = edges[k];
      if (ed.beta == 0) {  // horizontal: the whole row is on one side
        if (ed.side(xs, Y) < 0) xs = xe + 1;
        continue;
      }
      // The crossing in floating point is accurate far below a pixel; the
      // exact side decides the integer bound.
      const double cross = std::clamp(ed.u.x + (Y - ed.u.y) * slope[k], double(x_min) - 1, double(x_max) + 1);
      if (ed.beta > 0) {  // inside for X left of the crossing: a right bound
        int x = std::min(xe, static_cast<int>(std::floor(cross)));
        while (x + 1 <= xe && ed.side(x + 1, Y) > 0) ++x;
        while (x >= xs && ed.side(x, Y) < 0) --x;
        xe = x;
      } else {  // a left bound
        int x = std::max(xs, static_cast<int>(std::ceil(cross)));
        while (x - 1 >= xs && ed.side(x - 1, Y) > 0) --x;
        while (x <= xe && ed.side(x, Y) < 0) ++x;
        xs = x;
      }
    }
    if (xs > xe) continue;
    float* px = &out.pixels[out.index(xs, y - row0)];
    unsigned char* h = hits + static_cast<std::size_t>(y - row_begin) * W;
    for (int x = xs; x <= xe; ++x)
      if (h[x] < 255) ++h[x];
    if (!cubic) {
      double base[max_channels];
      for (int c = 0; c < C; ++c) base[c] = v0[c] + (Y - p0.y) * sy[c] + (xs - p0.x) * sx[c];
      for (int x = xs; x <= xe; ++x, px += C) {
        const double dx = x - xs;
        for (int c = 0; c < C; ++c) px[c] = static_cast<float>(base[c] + dx * sx[c]);
      }
      continue;
    }
    const double r1 = ax * (Y - p2.y), r2 = bx * (Y - p0.y);
    for (int x = xs; x <= xe; ++x, px += C) {
      const double l1 = (r1 - ay * (x - p2.x)) * inv1;
      const double l2 = (r2 - by * (x - p0.x)) * inv2;
      const double l0 = 1.0 - l1 - l2;
      const double l00 = l0 * l0, l11 = l1 * l1, l22 = l2 * l2;
      const double m[10] = {l00 * l0, l11 * l1, l22 * l2, l00 * l1, l0 * l11,
                            l11 * l2, l1 * l22, l0 * l22, l00 * l2, l0 * l1 * l2};
      for (int c = 0; c < C; ++c) {
        double v = 0;
        for (int q = 0; q < 10; ++q) v += b[c][q] * m[q];
        px[c] = static_cast<float>(std::clamp(v, lo[c], hi[c]));
      }
    }
  }
}

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

// Rows [first, last] (clipped to [row0, row1)) a triangle may own.
void row_range(const Scene& scene, index_t t, int row0, int row1, int& first, int& last) {
  index_t id[3];
  scene.corners(t, id);
  double lo = scene.pos(id[0]).y, hi = lo;
  for (int k = 1; k < 3; ++k) {
    const double y = scene.pos(id[k]).y;
    lo = std::min(lo, y), hi = std::max(hi, y);
  }
  first = static_cast<int>(std::max(double(row0), std::ceil(lo)));
  last = static_cast<int>(std::min(double(row1 - 1), std::floor(hi)));
  if (first > last) first = row0, last = row0 - 1;
}

}  // namespace

Image render_mesh(const Mesh2& mesh, const std::vector<float>& values, int C, const RenderGrid& grid,
                  RenderStats* stats, bool fill_outside, float outside_value, const std::vector<float>* gradients,
                  Progress* progress) {
  if (gradients && (gradients->size() != values.size() * 2 || C > max_channels))
    throw Error("render_mesh: cubic mode needs #V x C x 2 gradients and at most 16 channels");
  if (C > max_channels) throw Error("render_mesh: at most 16 channels");
  RenderStats local;
  const int row0 = grid.rows < 0 ? 0 : std::clamp(grid.first_row, 0, grid.height);
  const int row1 = grid.rows < 0 ? grid.height : std::clamp(grid.first_row + grid.rows, row0, grid.height);
  if (mesh.triangle_count() == 0) {
    if (stats) *stats = local;
    if (!fill_outside) return Image(grid.width, row1 - row0, C, outside_value);
    return render_collinear(mesh, values, C, grid, row0, row1);
  }
  Scene scene{mesh, values, C, grid};
  scene.gradients = gradients;
  scene.V = static_cast<index_t>(mesh.points.size());
  scene.T = mesh.triangle_count();
  if (fill_outside) add_rim(scene);
  local.triangles = scene.T;
  local.rim_triangles = static_cast<long long>(scene.rim_tris.size() / 3);
  scene.mesh_exact = grid.width <= 32768 && grid.height <= 32768;
  for (index_t v = 0; v < scene.V && scene.mesh_exact; ++v) {
    const Point2 p = scene.pos(v);
    scene.mesh_exact = exact_coordinate(p.x) && exact_coordinate(p.y);
  }
  scene.rim_exact.resize(scene.rim_points.size());
  for (std::size_t i = 0; i < scene.rim_points.size(); ++i) {
    const Point2 p = scene.pos(scene.V + static_cast<index_t>(i));
    scene.rim_exact[i] = scene.mesh_exact && exact_coordinate(p.x) && exact_coordinate(p.y);
  }

  // Bin triangles by bands of rows (a counting sort over fixed chunks of
  // triangles); bands are drawn in parallel and own their pixels, so no two
  // threads write the same pixel.
  const int bands = (row1 - row0 + band_rows - 1) / band_rows;
  const index_t n_tris = scene.triangle_count();
  const index_t chunk = std::max<index_t>(1 << 14, (n_tris + 255) / 256);
  const int chunks = static_cast<int>((n_tris + chunk - 1) / chunk);
  std::vector<std::size_t> offset(static_cast<std::size_t>(chunks) * bands + 1, 0);  // [chunk][band] -> count, then start
  auto slot = [&](int k, int b) -> std::size_t& { return offset[static_cast<std::size_t>(b) * chunks + k]; };
  tbb::parallel_for(0, chunks, [&](int k) {
    for (index_t t = k * chunk; t < std::min(n_tris, (k + 1) * chunk); ++t) {
      int first, last;
      row_range(scene, t, row0, row1, first, last);
      for (int b = (first - row0) / band_rows; first <= last && b <= (last - row0) / band_rows; ++b) ++slot(k, b);
    }
  });
  std::size_t running = 0;
  for (std::size_t& o : offset) {  // band-major: each band's triangles contiguous, in triangle order
    const std::size_t count = o;
    o = running;
    running += count;
  }
  std::vector<index_t> binned(running);
  tbb::parallel_for(0, chunks, [&](int k) {
    std::vector<std::size_t> cursor(bands);
    for (int b = 0; b < bands; ++b) cursor[b] = slot(k, b);
    for (index_t t = k * chunk; t < std::min(n_tris, (k + 1) * chunk); ++t) {
      int first, last;
      row_range(scene, t, row0, row1, first, last);
      for (int b = (first - row0) / band_rows; first <= last && b <= (last - row0) / band_rows; ++b)
        binned[cursor[b]++] = t;
    }
  });
  auto band_begin = [&](int b) { return offset[static_cast<std::size_t>(b) * chunks]; };
  auto band_end = [&](int b) { return b + 1 < bands ? offset[static_cast<std::size_t>(b + 1) * chunks] : running; };

  if (progress) progress->begin("render", bands);
  Image out(grid.width, row1 - row0, C, outside_value);
  std::vector<long long> band_uncovered(bands, 0), band_overcovered(bands, 0);
  std::vector<std::vector<std::pair<int, int>>> holes(bands);  // uncovered pixels (x, y)
  auto draw = [&](index_t t, int row_begin, int row_end, unsigned char* hits) {
    switch (C) {
      case 1: draw_triangle<1>(scene, t, row_begin, row_end, row0, out, hits); break;
      case 3: draw_triangle<3>(scene, t, row_begin, row_end, row0, out, hits); break;
      case 4: draw_triangle<4>(scene, t, row_begin, row_end, row0, out, hits); break;
      default: draw_triangle<0>(scene, t, row_begin, row_end, row0, out, hits); break;
    }
  };
  tbb::parallel_for(0, bands, [&](int b) {
    const int row_begin = row0 + b * band_rows, row_end = std::min(row1, row_begin + band_rows);
    std::vector<unsigned char> hits(static_cast<std::size_t>(row_end - row_begin) * grid.width, 0);
    for (std::size_t i = band_begin(b); i < band_end(b); ++i) draw(binned[i], row_begin, row_end, hits.data());
    for (std::size_t i = 0; i < hits.size(); ++i) {
      if (hits[i] == 0) {
        ++band_uncovered[b];
        if (fill_outside)
          holes[b].emplace_back(static_cast<int>(i % grid.width), row_begin - row0 + static_cast<int>(i / grid.width));
      }
      if (hits[i] > 1) ++band_overcovered[b];
    }
    if (progress) progress->add(1);
  });
  for (int b = 0; b < bands; ++b) local.uncovered += band_uncovered[b], local.overcovered += band_overcovered[b];

  // Samples that fall on pixel centres are written exactly (the plane and
  // the patch equal the vertex value there up to rounding).
  std::vector<char> used(scene.V, 0);
  for (index_t v : mesh.tri) used[v] = 1;
  tbb::parallel_for(index_t(0), scene.V, [&](index_t v) {
    if (!used[v]) return;
    const Point2 p = scene.pos(v);
    if (p.x != std::floor(p.x) || p.y != std::floor(p.y)) return;
    if (p.x < 0 || p.y < row0 || p.x >= grid.width || p.y >= row1) return;
    const float* z = scene.value(v);
    float* px = &out.pixels[out.index(static_cast<int>(p.x), static_cast<int>(p.y) - row0)];
    for (int c = 0; c < C; ++c) px[c] = z[c];
  });

  if (fill_outside && local.uncovered > 0) {
    // Only slivers collapsed by rounding can leave a hole; copy a neighbour
    // (in raster order, so a filled hole can feed the next).
    for (const auto& band : holes)
      for (auto [x, y] : band) {
        const int sx = x > 0 ? x - 1 : std::min(x + 1, grid.width - 1);
        const int sy = x > 0 || grid.width > 1 ? y : (y > 0 ? y - 1 : std::min(y + 1, out.height - 1));
        for (int c = 0; c < C; ++c) out.at(x, y, c) = out.at(sx, sy, c);
      }
  }
  if (stats) *stats = local;
  return out;
}

}  // namespace ddt
