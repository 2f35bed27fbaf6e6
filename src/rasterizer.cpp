#include "rasterizer.hpp"

#include "cubic_surface.hpp"
#include "error.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace ddt {
namespace {

constexpr int band_rows = 16;

// Side of p relative to the directed line u->v with the exact predicate and
// the (eps, eps^2) perturbation of p on ties: +1 left, -1 right, never 0.
// Antisymmetric in (u, v), so two triangles sharing an edge never both own
// a point on it.
int side(const Point2& u, const Point2& v, const Point2& p) {
  const int s = orientation(u, v, p);
  if (s != 0) return s;
  // d/dx of the orientation determinant is (u.y - v.y), d/dy is (v.x - u.x).
  if (u.y != v.y) return u.y > v.y ? 1 : -1;
  return v.x > u.x ? 1 : -1;
}

struct Soup {
  std::vector<Point2> pos;      // output pixel space: pixel centres at integers
  std::vector<float> values;    // #pos by C
  std::vector<index_t> tris;    // counter-clockwise triples
  // Cubic mode only: the mesh's input positions and per-vertex gradients
  // (#V by C by 2), and the Bézier control values of each rim triangle
  // (triangles from mesh_triangles on), C patches each.
  const std::vector<Point2>* input_points = nullptr;
  const std::vector<float>* gradients = nullptr;
  index_t mesh_triangles = 0;
  std::vector<std::array<double, 10>> rim_patches;
};

// The cubic patch of soup triangle t for channel c.
std::array<double, 10> soup_patch(const Soup& soup, int C, index_t t, int c) {
  if (t >= soup.mesh_triangles) return soup.rim_patches[static_cast<std::size_t>(t - soup.mesh_triangles) * C + c];
  const index_t i0 = soup.tris[3 * t], i1 = soup.tris[3 * t + 1], i2 = soup.tris[3 * t + 2];
  const auto& P = *soup.input_points;
  const auto& G = *soup.gradients;
  auto grad = [&](index_t v) { return &G[(static_cast<std::size_t>(v) * C + c) * 2]; };
  double g0[2] = {grad(i0)[0], grad(i0)[1]}, g1[2] = {grad(i1)[0], grad(i1)[1]}, g2[2] = {grad(i2)[0], grad(i2)[1]};
  return cubic_patch(P[i0], P[i1], P[i2], soup.values[static_cast<std::size_t>(i0) * C + c],
                     soup.values[static_cast<std::size_t>(i1) * C + c],
                     soup.values[static_cast<std::size_t>(i2) * C + c], g0, g1, g2);
}

void draw_triangle(const Soup& soup, int C, index_t t, int row_begin, int row_end, Image& out,
                   std::vector<unsigned char>& hits) {
  const index_t i0 = soup.tris[3 * t], i1 = soup.tris[3 * t + 1], i2 = soup.tris[3 * t + 2];
  const Point2 &p0 = soup.pos[i0], &p1 = soup.pos[i1], &p2 = soup.pos[i2];
  if (orientation(p0, p1, p2) <= 0) return;  // collapsed by the output transform
  const double min_y = std::min({p0.y, p1.y, p2.y}), max_y = std::max({p0.y, p1.y, p2.y});
  const double min_x = std::min({p0.x, p1.x, p2.x}), max_x = std::max({p0.x, p1.x, p2.x});
  const int y_lo = std::max(row_begin, static_cast<int>(std::ceil(min_y)));
  const int y_hi = std::min(row_end - 1, static_cast<int>(std::floor(max_y)));
  if (y_lo > y_hi) return;

  // lambda1 = E20(p) / d1, lambda2 = E01(p) / d2: the same arithmetic as the
  // denominators, so the weights are exactly 1 and 0 at the vertices.
  const double ax = p0.x - p2.x, ay = p0.y - p2.y;  // E20(p) = ax (py - p2y) - ay (px - p2x)
  const double bx = p1.x - p0.x, by = p1.y - p0.y;  // E01(p) = bx (py - p0y) - by (px - p0x)
  const double d1 = ax * (p1.y - p2.y) - ay * (p1.x - p2.x);
  const double d2 = bx * (p2.y - p0.y) - by * (p2.x - p0.x);
  double v0[16], dv1[16], dv2[16];
  const float* z0 = &soup.values[static_cast<std::size_t>(i0) * C];
  const float* z1 = &soup.values[static_cast<std::size_t>(i1) * C];
  const float* z2 = &soup.values[static_cast<std::size_t>(i2) * C];
  for (int c = 0; c < C; ++c) {
    v0[c] = z0[c];
    dv1[c] = double(z1[c]) - z0[c];
    dv2[c] = double(z2[c]) - z0[c];
  }
  const bool cubic = soup.gradients != nullptr;
  std::array<std::array<double, 10>, 16> patch;
  // The cubic stays within its triangle's vertex values: no overshoot, so
  // no ringing beside edges, whatever the gradients say.
  double lo[16], hi[16];
  if (cubic)
    for (int c = 0; c < C; ++c) {
      patch[c] = soup_patch(soup, C, t, c);
      lo[c] = std::min({double(z0[c]), double(z1[c]), double(z2[c])});
      hi[c] = std::max({double(z0[c]), double(z1[c]), double(z2[c])});
    }
  const Point2* edge[3][2] = {{&p0, &p1}, {&p1, &p2}, {&p2, &p0}};
  auto inside = [&](int x, int y) {
    const Point2 p{double(x), double(y)};
    return side(p0, p1, p) > 0 && side(p1, p2, p) > 0 && side(p2, p0, p) > 0;
  };
  const int W = out.width;
  for (int y = y_lo; y <= y_hi; ++y) {
    double xl = max_x, xr = min_x;
    for (const auto& ed : edge) {
      const Point2 &u = *ed[0], &v = *ed[1];
      if (u.y == v.y || y < std::min(u.y, v.y) || y > std::max(u.y, v.y)) continue;
      const double x = std::clamp(u.x + (y - u.y) * (v.x - u.x) / (v.y - u.y), min_x, max_x);
      xl = std::min(xl, x);
      xr = std::max(xr, x);
    }
    if (xl > xr) {  // only horizontal edges at this row: the row is an edge
      xl = min_x;
      xr = max_x;
    }
    // The float crossings are accurate far below a pixel; widen by one and
    // let the exact test trim. Covered centres form one interval per row.
    int xs = std::max(0, static_cast<int>(std::floor(xl)) - 1);
    int xe = std::min(W - 1, static_cast<int>(std::ceil(xr)) + 1);
    while (xs <= xe && !inside(xs, y)) ++xs;
    while (xe >= xs && !inside(xe, y)) --xe;
    if (xs > xe) continue;
    const double r1 = ax * (y - p2.y), r2 = bx * (y - p0.y);
    float* row = &out.pixels[out.index(0, y)];
    unsigned char* row_hits = &hits[static_cast<std::size_t>(y) * W];
    for (int x = xs; x <= xe; ++x) {
      const double l1 = (r1 - ay * (x - p2.x)) / d1;
      const double l2 = (r2 - by * (x - p0.x)) / d2;
      float* px = row + static_cast<std::size_t>(x) * C;
      if (cubic) {
        const double l0 = 1.0 - l1 - l2;
        for (int c = 0; c < C; ++c)
          px[c] = static_cast<float>(std::clamp(eval_cubic_patch(patch[c], l0, l1, l2), lo[c], hi[c]));
      } else {
        for (int c = 0; c < C; ++c) px[c] = static_cast<float>(v0[c] + l1 * dv1[c] + l2 * dv2[c]);
      }
      if (row_hits[x] < 255) ++row_hits[x];
    }
  }
}

// Adds the slabs and corner fans that extend the hull's values outward.
// Built in input coordinates (distances there define "nearest"), far enough
// that the output domain is covered.
void add_rim(const Mesh2& mesh, const std::vector<float>& values, int C, const RenderGrid& grid,
             std::vector<Point2>& input_pos, Soup& soup) {
  const index_t n_half = mesh.half_edge_count();
  std::vector<index_t> outgoing(mesh.points.size(), no_edge);  // hull vertex -> its hull half-edge
  std::vector<index_t> hull;
  for (index_t e = 0; e < n_half; ++e)
    if (mesh.opp[e] == no_edge) {
      outgoing[mesh.tri[e]] = e;
      hull.push_back(e);
    }
  if (hull.empty()) return;
  double lo_x = grid.origin_x, hi_x = grid.origin_x + grid.width / grid.scale_x;
  double lo_y = grid.origin_y, hi_y = grid.origin_y + grid.height / grid.scale_y;
  for (const Point2& p : mesh.points) {
    lo_x = std::min(lo_x, p.x), hi_x = std::max(hi_x, p.x);
    lo_y = std::min(lo_y, p.y), hi_y = std::max(hi_y, p.y);
  }
  const double far = 2.0 * std::hypot(hi_x - lo_x, hi_y - lo_y) + 1.0;

  auto add_vertex = [&](const Point2& p, index_t value_of) {
    input_pos.push_back(p);
    soup.values.insert(soup.values.end(), values.begin() + static_cast<std::ptrdiff_t>(value_of) * C,
                       values.begin() + static_cast<std::ptrdiff_t>(value_of + 1) * C);
    return static_cast<index_t>(input_pos.size() - 1);
  };
  auto normal_of = [&](index_t e) {
    const Point2& u = mesh.points[mesh.tri[e]];
    const Point2& v = mesh.points[mesh.tri[next_edge(e)]];
    const double len = std::hypot(v.x - u.x, v.y - u.y);
    return Point2{(v.y - u.y) / len, -(v.x - u.x) / len};  // right of u->v: outside
  };
  // far_start[e], far_end[e]: the slab's outer corners, shared with the fans.
  std::vector<index_t> far_start(n_half, no_edge), far_end(n_half, no_edge);
  for (index_t e : hull) {
    const index_t u = mesh.tri[e], v = mesh.tri[next_edge(e)];
    const Point2 n = normal_of(e);
    const Point2 &pu = mesh.points[u], &pv = mesh.points[v];
    far_start[e] = add_vertex({pu.x + far * n.x, pu.y + far * n.y}, u);
    far_end[e] = add_vertex({pv.x + far * n.x, pv.y + far * n.y}, v);
    soup.tris.insert(soup.tris.end(), {v, u, far_start[e]});
    soup.tris.insert(soup.tris.end(), {v, far_start[e], far_end[e]});
    if (soup.gradients) {
      // The slab's value is the hull edge's cubic at the nearest edge point,
      // a function of t, the position along u->v. In (v, u, Fu), t = l0; in
      // (v, Fu, Fv), t = l0 + l2. A Bézier triangle of a function of
      // l0 (+ l2) has control value d[i] (d[i + k]) at index ijk.
      for (int pass = 0; pass < 2; ++pass)
        for (int c = 0; c < C; ++c) {
          const float* gu = &(*soup.gradients)[(static_cast<std::size_t>(u) * C + c) * 2];
          const float* gv = &(*soup.gradients)[(static_cast<std::size_t>(v) * C + c) * 2];
          const double dx = pv.x - pu.x, dy = pv.y - pu.y;
          const double zu = values[static_cast<std::size_t>(u) * C + c], zv = values[static_cast<std::size_t>(v) * C + c];
          const double d[4] = {zu, zu + (gu[0] * dx + gu[1] * dy) / 3, zv - (gv[0] * dx + gv[1] * dy) / 3, zv};
          // order: 300, 030, 003, 210, 120, 021, 012, 102, 201, 111 as (i, k) of l0, l2 powers
          const int ik[10][2] = {{3, 0}, {0, 0}, {0, 3}, {2, 0}, {1, 0}, {0, 1}, {0, 2}, {1, 2}, {2, 1}, {1, 1}};
          std::array<double, 10> b;
          for (int q = 0; q < 10; ++q) b[q] = d[pass == 0 ? ik[q][0] : ik[q][0] + ik[q][1]];
          soup.rim_patches.push_back(b);
        }
    }
  }
  const double max_piece = M_PI / 3;  // keeps each fan triangle's far side beyond `far` * cos(30deg)
  for (index_t e_in : hull) {
    const index_t v = mesh.tri[next_edge(e_in)];
    const index_t e_out = outgoing[v];
    const Point2 n_in = normal_of(e_in), n_out = normal_of(e_out);
    const double turn = std::atan2(n_in.x * n_out.y - n_in.y * n_out.x, n_in.x * n_out.x + n_in.y * n_out.y);
    if (!(turn > 0)) continue;  // collinear hull vertex: slabs already meet
    const int pieces = static_cast<int>(std::ceil(turn / max_piece));
    const Point2& pv = mesh.points[v];
    index_t previous = far_end[e_in];
    for (int k = 1; k <= pieces; ++k) {
      index_t next_far = far_start[e_out];
      if (k < pieces) {
        const double a = turn * k / pieces, ca = std::cos(a), sa = std::sin(a);
        const Point2 dir{n_in.x * ca - n_in.y * sa, n_in.x * sa + n_in.y * ca};
        next_far = add_vertex({pv.x + far * dir.x, pv.y + far * dir.y}, v);
      }
      soup.tris.insert(soup.tris.end(), {v, previous, next_far});
      if (soup.gradients)
        for (int c = 0; c < C; ++c) {
          std::array<double, 10> b;
          b.fill(values[static_cast<std::size_t>(v) * C + c]);
          soup.rim_patches.push_back(b);
        }
      previous = next_far;
    }
  }
}

Image render_collinear(const Mesh2& mesh, const std::vector<float>& values, int C, const RenderGrid& grid) {
  Image out(grid.width, grid.height, C);
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
  tbb::parallel_for(0, grid.height, [&](int Y) {
    for (int X = 0; X < grid.width; ++X) {
      const double x = grid.origin_x + (X + 0.5) / grid.scale_x, y = grid.origin_y + (Y + 0.5) / grid.scale_y;
      const double t = len2 > 0 ? ((x - P[first].x) * dx + (y - P[first].y) * dy) / len2 : 0.0;
      auto hi = std::lower_bound(order.begin(), order.end(), std::make_pair(t, index_t(-1)));
      float* px = &out.pixels[out.index(X, Y)];
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

}  // namespace

Image render_mesh(const Mesh2& mesh, const std::vector<float>& values, int C, const RenderGrid& grid,
                  RenderStats* stats, bool fill_outside, float outside_value, const std::vector<float>* gradients) {
  if (gradients && (gradients->size() != values.size() * 2 || C > 16))
    throw Error("render_mesh: cubic mode needs #V x C x 2 gradients and at most 16 channels");
  RenderStats local;
  if (mesh.triangle_count() == 0) {
    if (stats) *stats = local;
    if (!fill_outside) return Image(grid.width, grid.height, C, outside_value);
    return render_collinear(mesh, values, C, grid);
  }
  Soup soup;
  std::vector<Point2> input_pos(mesh.points);
  soup.values = values;
  soup.tris = mesh.tri;
  soup.mesh_triangles = mesh.triangle_count();
  soup.input_points = &mesh.points;
  soup.gradients = gradients;
  if (fill_outside) add_rim(mesh, values, C, grid, input_pos, soup);
  local.triangles = mesh.triangle_count();
  local.rim_triangles = static_cast<long long>(soup.tris.size() / 3) - local.triangles;
  soup.pos.resize(input_pos.size());
  for (std::size_t i = 0; i < input_pos.size(); ++i)
    soup.pos[i] = {(input_pos[i].x - grid.origin_x) * grid.scale_x - 0.5,
                   (input_pos[i].y - grid.origin_y) * grid.scale_y - 0.5};

  // Bin triangles by bands of rows; bands are drawn in parallel and own
  // their pixels, so no two threads write the same pixel.
  const int bands = (grid.height + band_rows - 1) / band_rows;
  std::vector<std::vector<index_t>> band_tris(bands);
  const index_t n_tris = static_cast<index_t>(soup.tris.size() / 3);
  for (index_t t = 0; t < n_tris; ++t) {
    double lo = soup.pos[soup.tris[3 * t]].y, hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = std::min(lo, soup.pos[soup.tris[3 * t + k]].y);
      hi = std::max(hi, soup.pos[soup.tris[3 * t + k]].y);
    }
    const int r0 = std::max(0, static_cast<int>(std::ceil(lo)));
    const int r1 = std::min(grid.height - 1, static_cast<int>(std::floor(hi)));
    for (int b = r0 / band_rows; r0 <= r1 && b <= r1 / band_rows; ++b) band_tris[b].push_back(t);
  }
  Image out(grid.width, grid.height, C, outside_value);
  std::vector<unsigned char> hits(out.pixel_count(), 0);
  tbb::parallel_for(0, bands, [&](int b) {
    const int row_begin = b * band_rows, row_end = std::min(grid.height, row_begin + band_rows);
    for (index_t t : band_tris[b]) draw_triangle(soup, C, t, row_begin, row_end, out, hits);
  });
  for (unsigned char h : hits) {
    if (h == 0) ++local.uncovered;
    if (h > 1) ++local.overcovered;
  }
  if (fill_outside && local.uncovered > 0) {
    // Only slivers collapsed by rounding can leave a hole; copy a neighbour.
    for (int y = 0; y < grid.height; ++y)
      for (int x = 0; x < grid.width; ++x) {
        if (hits[static_cast<std::size_t>(y) * grid.width + x]) continue;
        const int sx = x > 0 ? x - 1 : std::min(x + 1, grid.width - 1);
        const int sy = x > 0 || grid.width > 1 ? y : (y > 0 ? y - 1 : std::min(y + 1, grid.height - 1));
        for (int c = 0; c < C; ++c) out.at(x, y, c) = out.at(sx, sy, c);
      }
  }
  if (stats) *stats = local;
  return out;
}

}  // namespace ddt
