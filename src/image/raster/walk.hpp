#pragma once
// The walk: exact row crossings of an edge (Bresenham stepping on exact
// coordinates), a triangle's piece of a group of rows, and the walks across
// the mesh's adjacency that draw each group left to right.

#include "image/raster/shader.hpp"
#include "util/error.hpp"

#include <utility>
#include <vector>

namespace ddt::raster {

// The downward edge u->v (u.y < v.y) of the triangle on its left: that
// triangle owns a pixel centre of a row crossing the edge when the centre
// is left of it (side > 0), the triangle on its right otherwise.
struct Crossing {
  Edge edge;
  Crossing(const Point2& u, const Point2& v, bool exact) : edge{u, v, v.x - u.x, v.y - u.y, tie_side(u, v), exact} {}
  // x[r]: the first pixel of row g + r right of the edge, clamped to [0, W],
  // for the m rows from g (all crossing the edge).
  void first_right(int g, int m, int W, int* x) const {
    const double alpha = edge.alpha, beta = edge.beta;
    if (edge.exact) {
      // The crossing is n / beta with n = alpha (Y - u.y) + beta u.x exact
      // (an edge function); the first pixel is its ceiling b, ties included
      // (side -1 on the line). The quotient rounds to an integer only when
      // it is one: otherwise it is at least 2^-20 / 2^16 from one, more than
      // half an ulp of numbers below 2^16 (the crossing lies on the edge).
      // Row to row, n grows by alpha = qa beta + ra (0 <= ra < beta), so b
      // steps by qa or qa + 1 as the remainder n - b beta in (-beta, 0]
      // says (Bresenham's stepping; all exact).
      const double n = alpha * (g - edge.u.y) + beta * edge.u.x;
      int b = ceil_int(n / beta);
      double remainder = n - b * beta;
      const int qa = m > 1 ? floor_int(alpha / beta) : 0;  // |alpha / beta| < 2^26, ulp/2 < 2^-10 / 2^16
      const double ra = alpha - qa * beta;
      for (int r = 0; r < m; ++r) {
        x[r] = std::clamp(b, 0, W);
        remainder += ra;
        const bool carry = remainder > 0;
        b += qa + carry;
        remainder -= carry ? beta : 0.0;
      }
      return;
    }
    // A floating-point estimate, then the exact side of the pixels beside it.
    const double slope = alpha / beta;
    for (int r = 0; r < m; ++r) {
      const int Y = g + r;
      const double x_cross = edge.u.x + (Y - edge.u.y) * slope;
      int c = std::clamp(ceil_int(std::clamp(x_cross, -1.0, W + 1.0)), 0, W);
      while (c > 0 && edge.side(c - 1, Y) < 0) --c;
      while (c < W && edge.side(c, Y) > 0) ++c;
      x[r] = c;
    }
  }
};

// A triangle that owns pixels: corners in pixels, and its shader.
template <int CT, bool cubic>
struct Piece {
  const index_t* id;
  const Point2* p;
  bool exact;  // all corners exact: edge functions at pixel centres are exact
  Shader<CT, cubic> shader;

  // pixels: how many it draws (the cubic picks its form by them).
  Piece(const Scene& scene, index_t t, const index_t corner[3], const Point2 position[3], bool all_exact,
        long long pixels)
      : id(corner), p(position), exact(all_exact) {
    const double area2 = signed_area2(p[0], p[1], p[2]);
    shader.init(scene, t, id, p[0], p[1], p[2], area2, pixels);
  }

  // Its pixels [left[r], right[r]) of grid rows g + r, r < m.
  void draw(int g, int m, const int* left, const int* right, Image& out, int shift) const {
    if constexpr (cubic) {
      if (!shader.by_power && exact) return draw_bernstein(g, m, left, right, out, shift);
    }
    for (int r = 0; r < m; ++r)
      if (right[r] > left[r]) span(g + r, left[r], right[r] - 1, &out.pixels[out.index(left[r], g + r - shift)]);
  }

  // Cubic, Bernstein form, exact corners: the pixels of all rows paired in
  // reading order, so rows of one or three pixels (small scales) waste no
  // lanes. The edge functions E_k of edges p_k -> p_(k+1) are exact at
  // pixel centres (multiples of 2^-20 below 2^33), so stepping them along a
  // row is too; E_k / area2 is the weight of the vertex opposite edge k.
  void draw_bernstein(int g, int m, const int* left, const int* right, Image& out, int shift) const {
    const int C = shader.C;
    const double inv = shader.inv_area2;
    bool held = false;  // a pixel waiting for its pair
    double h0 = 0, h1 = 0, h2 = 0;
    float* held_px = nullptr;
    for (int r = 0; r < m; ++r) {
      const int y = g + r, xs = left[r], xe = right[r];
      if (xe <= xs) continue;
      double e[3], step[3];
      for (int k = 0; k < 3; ++k) {
        const Point2 &u = p[k], &v = p[(k + 1) % 3];
        e[k] = (v.x - u.x) * (y - u.y) - (v.y - u.y) * (xs - u.x), step[k] = -(v.y - u.y);
      }
      float* px = &out.pixels[out.index(xs, y - shift)];
      for (int x = xs; x < xe; ++x, px += C) {
        const double l0 = e[1] * inv, l1 = e[2] * inv, l2 = e[0] * inv;
        if (held)
          shader.pixel_pair(v2d{h0, l0}, v2d{h1, l1}, v2d{h2, l2}, held_px, px);
        else
          h0 = l0, h1 = l1, h2 = l2, held_px = px;
        held = !held;
        for (int k = 0; k < 3; ++k) e[k] += step[k];
      }
    }
    if (held) shader.pixel(h0, h1, h2, held_px);
  }

  // Pixels xs..xe (xs <= xe) of grid row y, at px.
  void span(int y, int xs, int xe, float* px) const {
    if constexpr (!cubic) {
      shader.row(y, xs, xe, px);
    } else {
      if (shader.by_power) {
        shader.power_row(y, xs, xe, px);
        return;
      }
      // Weights from the edge functions of p1->p2 and p2->p0 (of p0 and p1).
      const double inv = shader.inv_area2, Y = y;
      const Point2 &a = p[1], &b = p[2];
      for (int x = xs; x <= xe; ++x, px += shader.C) {
        const double l0 = ((b.x - a.x) * (Y - a.y) - (b.y - a.y) * (x - a.x)) * inv;
        const double l1 = ((p[0].x - b.x) * (Y - b.y) - (p[0].y - b.y) * (x - b.x)) * inv;
        shader.pixel(l0, l1, 1.0 - l0 - l1, px);
      }
    }
  }
};

// Rows [g, g + m) hold no vertex strictly between them (no vertex y in
// (g, g + m - 1]), so the same triangles cross every row of the group, in
// the same order. A walk starts at an upward boundary half-edge (the left
// bound of the first triangle) and crosses each triangle's downward
// crossing edge to the next.

// One walk to trace: its start and its rows' first row; the triangles met,
// each with the slot of its downward crossing edge.
constexpr int walk_batch = 4;  // walks traced together

struct Walk {
  index_t start;
  int g;
  std::vector<std::pair<index_t, int>> crossed;
};

// Traces the walks together, a step of each in turn: each step is a chain
// of dependent loads (twin, corners, positions), and independent chains
// overlap. n <= walk_batch. A walk ends at the boundary, or before a
// triangle below stop_below.
inline void trace_walks(const Scene& scene, Walk* walks, int n, index_t stop_below) {
  index_t e[walk_batch];
  int live = 0;
  for (int i = 0; i < n; ++i) e[i] = walks[i].start, walks[i].crossed.clear(), ++live;
  const std::size_t limit = static_cast<std::size_t>(scene.triangle_count());
  while (live > 0)
    for (int i = 0; i < n; ++i) {
      if (e[i] == no_edge) continue;
      const index_t t = tri_of(e[i]);
      index_t id[3];
      scene.corners(t, id);
      const double y0 = scene.pos(id[0]).y, y1 = scene.pos(id[1]).y, y2 = scene.pos(id[2]).y;
      // The downward edge across the rows: one, since the triangle is crossed.
      const int g = walks[i].g;
      // Without branches: which edge it is varies at random from step to step.
      const int down0 = (y0 <= g) & (y1 > g), down1 = (y1 <= g) & (y2 > g);
      const int k = (1 - down0) * (2 - down1);
      walks[i].crossed.emplace_back(t, k);
      e[i] = scene.twin(3 * t + k);
      if (e[i] != no_edge && tri_of(e[i]) < stop_below) e[i] = no_edge;  // drawn by shape (lattice meshes)
      if (e[i] == no_edge) --live;
      if (walks[i].crossed.size() > limit) throw Error("render_mesh: the mesh's adjacency is inconsistent");
    }
}

struct DrawCounts {
  long long pixels = 0, power_pieces = 0, bernstein_pieces = 0, shaped_triangles = 0;
};

// Draws a traced walk on rows [g, g + m): each triangle's part of a row is
// the pixels between its left and right crossings, and each crossing is
// computed once, for the two triangles beside it, so a walk draws every
// pixel at most once. Adds the pixels and pieces drawn to counts.
template <int CT, bool cubic>
void draw_walk(const Scene& scene, const Walk& walk, int m, int shift, Image& out, std::vector<int>& left,
               std::vector<int>& right, DrawCounts& counts) {
  const int W = out.width, g = walk.g;
  left.resize(m), right.resize(m);
  {
    const index_t a = scene.tail(walk.start), b = scene.tail(next_edge(walk.start));
    const Crossing boundary(scene.pos(b), scene.pos(a), scene.exact(a) && scene.exact(b));
    boundary.first_right(g, m, W, left.data());
  }
  for (const auto& [t, k] : walk.crossed) {
    index_t id[3];
    Point2 p[3];
    scene.corners(t, id);
    for (int i = 0; i < 3; ++i) p[i] = scene.pos(id[i]);
    const bool exact_a = scene.exact(id[k]), exact_b = scene.exact(id[(k + 1) % 3]);
    const Crossing bound(p[k], p[(k + 1) % 3], exact_a && exact_b);
    bound.first_right(g, m, W, right.data());
    long long pixels = 0;
    for (int r = 0; r < m; ++r) {
      // max: a triangle turned over by rounding (general coordinates) owns nothing.
      right[r] = std::max(left[r], right[r]);
      pixels += right[r] - left[r];
    }
    if (pixels > 0) {
      const Piece<CT, cubic> piece(scene, t, id, p, exact_a && exact_b && scene.exact(id[(k + 2) % 3]), pixels);
      piece.draw(g, m, left.data(), right.data(), out, shift);
      counts.pixels += pixels;
      if constexpr (cubic) ++(piece.shader.by_power ? counts.power_pieces : counts.bernstein_pieces);
    }
    std::swap(left, right);
  }
}

}  // namespace ddt::raster
