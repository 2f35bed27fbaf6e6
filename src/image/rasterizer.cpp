#include "image/rasterizer.hpp"

#include "image/cubic_surface.hpp"
#include "util/error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <mutex>
#include <numeric>
#include <optional>
#include <type_traits>

namespace ddt {
namespace {

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
  Scene(const Mesh2& m, const std::vector<float>& v, int channels, const RenderGrid& g)
      : mesh(m), values(v), C(channels), grid(g) {}

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
  // The rim of a convex hull overlaps no triangle; elsewhere its slabs can
  // reach over the mesh, and what they cover depends on the drawing order.
  bool hull_convex = false;

  index_t triangle_count() const { return T + static_cast<index_t>(rim_tris.size() / 3); }
  void corners(index_t t, index_t out[3]) const {
    const index_t* src = t < T ? &mesh.tri[3 * static_cast<std::size_t>(t)] : &rim_tris[3 * static_cast<std::size_t>(t - T)];
    out[0] = src[0], out[1] = src[1], out[2] = src[2];
  }
  const Point2& input_point(index_t v) const { return v < V ? mesh.points[v] : rim_points[v - V]; }
  // Output pixel space: pixel centres at integers.
  Point2 transform(const Point2& p) const {
    return {(p.x - grid.origin_x) * grid.scale_x - 0.5, (p.y - grid.origin_y) * grid.scale_y - 0.5};
  }
  // Computed where needed: as cheap as loading a stored copy, and no
  // memory to allocate (fresh pages cost more than the arithmetic).
  Point2 pos(index_t v) const { return transform(input_point(v)); }
  index_t source(index_t v) const { return v < V ? v : rim_source[v - V]; }
  const float* value(index_t v) const { return &values[static_cast<std::size_t>(source(v)) * C]; }
  bool exact(index_t v) const { return v < V ? mesh_exact : rim_exact[v - V] != 0; }

  // Half-edges: 3t + k runs from corner k of triangle t to corner k + 1
  // (mesh triangles first, then the rim's, as the triangle ids).
  // rim_twin[i] is the twin of rim half-edge 3T + i; hull_twin maps each
  // hull half-edge of the mesh to its rim twin (sorted).
  std::vector<index_t> hull;  // the mesh's hull half-edges
  std::vector<index_t> rim_twin;
  std::vector<std::pair<index_t, index_t>> hull_twin;
  index_t tail(index_t e) const {
    return e < 3 * T ? mesh.tri[e] : rim_tris[static_cast<std::size_t>(e - 3 * T)];
  }
  index_t twin(index_t e) const {
    if (e >= 3 * T) return rim_twin[static_cast<std::size_t>(e - 3 * T)];
    if (mesh.opp[e] != no_edge || hull_twin.empty()) return mesh.opp[e];
    const auto it = std::lower_bound(hull_twin.begin(), hull_twin.end(), std::make_pair(e, index_t(-1)));
    return it != hull_twin.end() && it->first == e ? it->second : no_edge;
  }
};

// floor and ceil for values well inside the int range (pixel coordinates,
// clamped by the callers): a truncation and a correction, much cheaper
// than std::floor without SSE4.1.
inline int floor_int(double v) {
  const int i = static_cast<int>(v);
  return i - (v < i);
}
inline int ceil_int(double v) {
  const int i = static_cast<int>(v);
  return i + (v > i);
}
// Clamps v into [lo, hi] before the conversion (coordinates of far rim
// vertices, in pixels, can exceed the int range).
inline double clamp_pixels(double v) { return std::clamp(v, -1e9, 1e9); }

bool exact_coordinate(double c) {
  // |c * 1024| < 2^25: the conversion is exact when c * 1024 is an integer.
  return std::abs(c) < 32768.0 && c * 1024.0 == static_cast<double>(static_cast<long long>(c * 1024.0));
}

// Adds the slabs and corner fans that extend the hull's values outward.
// Built in input coordinates (distances there define "nearest"), far enough
// that the output domain is covered.
void add_rim(Scene& scene) {
  const Mesh2& mesh = scene.mesh;
  const RenderGrid& grid = scene.grid;
  const std::vector<float>& values = scene.values;
  const int C = scene.C;
  const std::vector<index_t>& hull = scene.hull;
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
  double min_turn = 0, total_turn = 0;
  for (std::size_t k_in = 0; k_in < hull.size(); ++k_in) {
    const index_t e_in = hull[k_in];
    const index_t v = mesh.tri[next_edge(e_in)];
    const index_t e_out = outgoing_of(v);
    const std::size_t k_out = index_of(e_out);
    const Point2 n_in = normal_of(e_in), n_out = normal_of(e_out);
    const double turn = std::atan2(n_in.x * n_out.y - n_in.y * n_out.x, n_in.x * n_out.x + n_in.y * n_out.y);
    min_turn = std::min(min_turn, turn), total_turn += turn;
    // At a collinear hull vertex (turn 0, or below it by rounding) one flat
    // triangle joins the slabs, so the rim stays one ring of triangles.
    const int pieces = turn > 0 ? static_cast<int>(std::ceil(turn / max_piece)) : 1;
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
  // One convex hull cycle turns by 2 pi, never back (collinear: 0 or a
  // rounding below); holes, notches and separate parts do not.
  scene.hull_convex = min_turn > -1e-9 && std::abs(total_turn - 2 * M_PI) < 1e-6;
  // Twins: rim edges matched with each other and with the hull's.
  struct Side {
    index_t lo, hi, e;
  };
  std::vector<Side> sides;
  const index_t rim_base = 3 * scene.T, rim_half = static_cast<index_t>(scene.rim_tris.size());
  for (index_t i = 0; i < rim_half; ++i) {
    const index_t a = scene.rim_tris[i], b = scene.rim_tris[next_edge(i)];
    sides.push_back({std::min(a, b), std::max(a, b), rim_base + i});
  }
  for (index_t e : hull) {
    const index_t a = mesh.tri[e], b = mesh.tri[next_edge(e)];
    sides.push_back({std::min(a, b), std::max(a, b), e});
  }
  std::sort(sides.begin(), sides.end(), [](const Side& p, const Side& q) { return p.lo != q.lo ? p.lo < q.lo : p.hi < q.hi; });
  scene.rim_twin.assign(rim_half, no_edge);
  auto set_twin = [&](index_t e, index_t f) {
    if (e >= rim_base) scene.rim_twin[e - rim_base] = f;
    else scene.hull_twin.emplace_back(e, f);
  };
  for (std::size_t i = 0; i + 1 < sides.size(); ++i)
    if (sides[i].lo == sides[i + 1].lo && sides[i].hi == sides[i + 1].hi) {
      set_twin(sides[i].e, sides[i + 1].e), set_twin(sides[i + 1].e, sides[i].e);
      ++i;
    }
  std::sort(scene.hull_twin.begin(), scene.hull_twin.end());
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

// Two doubles, one SSE2 register: element-wise IEEE operations.
typedef double v2d __attribute__((vector_size(16)));

// The cubic's Bernstein monomials at barycentric weights (l0, l1, l2), in
// the order of the control values (300, 030, 003, 210, 120, 021, 012, 102,
// 201, 111), without their multinomial factors; one order of operations
// everywhere (the same bits by any path). T: double or v2d.
template <class T>
void bernstein_monomials(T l0, T l1, T l2, T* m) {
  const T l00 = l0 * l0, l11 = l1 * l1, l22 = l2 * l2;
  m[0] = l00 * l0, m[1] = l11 * l1, m[2] = l22 * l2, m[3] = l00 * l1, m[4] = l0 * l11, m[5] = l11 * l2;
  m[6] = l1 * l22, m[7] = l0 * l22, m[8] = l00 * l2, m[9] = l0 * l1 * l2;
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

// The cubic's power form pays for its conversion from about 16 pixels a
// piece (on a grid: slower at x5, 12.5 pixels a triangle, faster at x6,
// 18; measured). Its terms can cancel where the Bernstein form's cannot.
// With K = (longest edge)^2 / (twice the area), |a X| + |b Y| <= K inside
// the triangle (Cauchy-Schwarz), so the terms of degree n sum to at most
// K^n |e_ij|, and |e_ij| <= 24 times the largest control value: in all at
// most about 64 K^3 times it. The rounding of the operations that combine
// them stays below about 1e-8 of it for K <= 20 (7e-12 measured on 300
// triangles near K = 20), below a float's ulp. Thinner triangles (rim
// slabs, needles) keep the Bernstein form.
constexpr int power_form_min_pixels = 16;
constexpr double power_form_max_shape = 20;

double max_edge2(const Point2& p0, const Point2& p1, const Point2& p2) {
  auto d2 = [](const Point2& u, const Point2& v) { return (v.x - u.x) * (v.x - u.x) + (v.y - u.y) * (v.y - u.y); };
  return std::max({d2(p0, p1), d2(p1, p2), d2(p2, p0)});
}

template <int C>
using channels = std::integral_constant<int, C>;  // 0: known at run time only

// What a triangle paints: the plane through its vertex values (linear) or
// its Bézier patch (cubic), evaluated at pixel centres.
template <int CT, bool cubic>
struct Shader {
  int C;
  Point2 p0;
  double inv_area2;  // 1 / (twice the signed area), in pixels
  // Linear: value = v0 + (X - p0.x) sx + (Y - p0.y) sy (exact at p0; the
  // other vertices are written exactly afterwards, see render_mesh).
  double v0[max_channels], sx[max_channels], sy[max_channels];
  // Cubic: Bézier control values, the middle ones pre-scaled by 3 and 6,
  // and the clamp to the vertex values (no overshoot, so no ringing beside
  // edges, whatever the gradients say).
  double b[cubic ? max_channels : 1][10], lo[cubic ? max_channels : 1], hi[cubic ? max_channels : 1];
  // Cubic, a mesh triangle's piece of many pixels: the same patch in
  // power form, a polynomial in (X, Y) = (x - p0.x, y - p0.y), so that
  // along a row it is a cubic in X (six operations a pixel instead of
  // twenty). Coefficients of X^3, X^2, X^2 Y, X, X Y, X Y^2, 1, Y, Y^2,
  // Y^3, by channel.
  bool by_power = false;
  double power[cubic ? max_channels : 1][10];

  // Set up when the triangle turns out to own a pixel (many own none at
  // small scales).
  void init(const Scene& scene, index_t t, const index_t id[3], const Point2& q0, const Point2& p1, const Point2& p2,
            double area2, long long pixels) {
    C = CT > 0 ? CT : scene.C, p0 = q0, inv_area2 = 1.0 / area2;
    const float *z0 = scene.value(id[0]), *z1 = scene.value(id[1]), *z2 = scene.value(id[2]);
    const double ux = p1.x - p0.x, uy = p1.y - p0.y, vx = p2.x - p0.x, vy = p2.y - p0.y;
    if constexpr (cubic) {
      if (t < scene.T) {
        mesh_patches(scene, id);
        if (pixels >= power_form_min_pixels && max_edge2(p0, p1, p2) <= power_form_max_shape * area2) to_power(p1, p2);
        return;
      }
    }
    for (int c = 0; c < C; ++c) {
      const double dv1 = double(z1[c]) - z0[c], dv2 = double(z2[c]) - z0[c];
      if constexpr (!cubic) {
        v0[c] = z0[c];
        sx[c] = (dv1 * vy - dv2 * uy) * inv_area2;
        sy[c] = (dv2 * ux - dv1 * vx) * inv_area2;
      } else {
        const std::array<double, 10> patch = scene_patch(scene, t, id, c);
        for (int q = 0; q < 10; ++q) b[c][q] = patch[q] * (q < 3 ? 1.0 : q < 9 ? 3.0 : 6.0);
        lo[c] = std::min({double(z0[c]), double(z1[c]), double(z2[c])});
        hi[c] = std::max({double(z0[c]), double(z1[c]), double(z2[c])});
      }
    }
  }
  // Cubic, a mesh triangle: cubic_patch() of every channel, two channels
  // at a time (lane by lane the same operations in the same order, so the
  // same bits), pre-scaled and with the clamp range, as above.
  void mesh_patches(const Scene& scene, const index_t id[3]) {
    const Point2 &P0 = scene.mesh.points[id[0]], &P1 = scene.mesh.points[id[1]], &P2 = scene.mesh.points[id[2]];
    const float* Z[3] = {&scene.values[static_cast<std::size_t>(id[0]) * C], &scene.values[static_cast<std::size_t>(id[1]) * C],
                         &scene.values[static_cast<std::size_t>(id[2]) * C]};
    const float* G[3];
    for (int i = 0; i < 3; ++i) G[i] = &(*scene.gradients)[static_cast<std::size_t>(id[i]) * C * 2];
    const v2d three = {3.0, 3.0}, six = {6.0, 6.0}, half = {0.5, 0.5};
    // along(g, from, to) = (g.x (to.x - from.x) + g.y (to.y - from.y)) / 3
    const v2d d01x = v2d{P1.x - P0.x, P1.x - P0.x}, d01y = v2d{P1.y - P0.y, P1.y - P0.y};
    const v2d d10x = v2d{P0.x - P1.x, P0.x - P1.x}, d10y = v2d{P0.y - P1.y, P0.y - P1.y};
    const v2d d12x = v2d{P2.x - P1.x, P2.x - P1.x}, d12y = v2d{P2.y - P1.y, P2.y - P1.y};
    const v2d d21x = v2d{P1.x - P2.x, P1.x - P2.x}, d21y = v2d{P1.y - P2.y, P1.y - P2.y};
    const v2d d20x = v2d{P0.x - P2.x, P0.x - P2.x}, d20y = v2d{P0.y - P2.y, P0.y - P2.y};
    const v2d d02x = v2d{P2.x - P0.x, P2.x - P0.x}, d02y = v2d{P2.y - P0.y, P2.y - P0.y};
    for (int c = 0; c < C; c += 2) {
      const int c1 = c + 1 < C ? c + 1 : c;  // the last lane repeats an odd channel
      auto pair = [&](const float* a, int stride) { return v2d{double(a[c * stride]), double(a[c1 * stride])}; };
      const v2d z0 = pair(Z[0], 1), z1 = pair(Z[1], 1), z2 = pair(Z[2], 1);
      const v2d g0x = pair(G[0], 2), g0y = pair(G[0] + 1, 2), g1x = pair(G[1], 2), g1y = pair(G[1] + 1, 2),
                g2x = pair(G[2], 2), g2y = pair(G[2] + 1, 2);
      const v2d b3 = z0 + (g0x * d01x + g0y * d01y) / three;  // 210
      const v2d b4 = z1 + (g1x * d10x + g1y * d10y) / three;  // 120
      const v2d b5 = z1 + (g1x * d12x + g1y * d12y) / three;  // 021
      const v2d b6 = z2 + (g2x * d21x + g2y * d21y) / three;  // 012
      const v2d b7 = z2 + (g2x * d20x + g2y * d20y) / three;  // 102
      const v2d b8 = z0 + (g0x * d02x + g0y * d02y) / three;  // 201
      const v2d edge_mean = (b3 + b4 + b5 + b6 + b7 + b8) / six;
      const v2d vertex_mean = (z0 + z1 + z2) / three;
      const v2d b9 = edge_mean + half * (edge_mean - vertex_mean);
      const v2d q[10] = {z0, z1, z2, b3 * three, b4 * three, b5 * three, b6 * three, b7 * three, b8 * three, b9 * six};
      // std::min({z0, z1, z2}) and std::max: the first of equal values (signed zeros)
      const v2d mn0 = z1 < z0 ? z1 : z0, mx0 = z0 < z1 ? z1 : z0;
      const v2d mn = z2 < mn0 ? z2 : mn0, mx = mx0 < z2 ? z2 : mx0;
      for (int lane = 0; lane < (c1 > c ? 2 : 1); ++lane) {
        for (int k = 0; k < 10; ++k) b[c + lane][k] = q[k][lane];
        lo[c + lane] = mn[lane], hi[c + lane] = mx[lane];
      }
    }
  }
  // Bernstein to power form. In s = l1 = a X + b Y and t = l2 = c X + d Y
  // (both zero at p0; l0 = 1 - s - t) the patch is sum e_ij s^i t^j, with
  // e from the control values by a fixed integer matrix; each s^i t^j is
  // then expanded in X and Y.
  void to_power(const Point2& p1, const Point2& p2) {
    const double a = (p2.y - p0.y) * inv_area2, b_ = (p0.x - p2.x) * inv_area2;
    const double c_ = (p0.y - p1.y) * inv_area2, d = (p1.x - p0.x) * inv_area2;
    // Homogeneous products, coefficients of X^n, X^(n-1) Y, ..., Y^n.
    const double S2[3] = {a * a, 2 * a * b_, b_ * b_}, ST[3] = {a * c_, a * d + b_ * c_, b_ * d},
                 T2[3] = {c_ * c_, 2 * c_ * d, d * d};
    auto times = [](const double q[3], double u, double v, double out[4]) {  // q (u X + v Y)
      out[0] = u * q[0], out[1] = u * q[1] + v * q[0], out[2] = u * q[2] + v * q[1], out[3] = v * q[2];
    };
    double S3[4], S2T[4], ST2[4], T3[4];
    times(S2, a, b_, S3), times(S2, c_, d, S2T), times(T2, a, b_, ST2), times(T2, c_, d, T3);
    for (int c = 0; c < C; ++c) {
      const double* q = b[c];  // pre-scaled: 300, 030, 003, 3 x (210, 120, 021, 012, 102, 201), 6 x 111
      const double e01 = -3 * q[0] + q[8], e02 = 3 * q[0] + q[7] - 2 * q[8], e03 = -q[0] + q[2] - q[7] + q[8];
      const double e10 = -3 * q[0] + q[3], e11 = 6 * q[0] - 2 * q[3] - 2 * q[8] + q[9];
      const double e12 = -3 * q[0] + q[3] + q[6] - q[7] + 2 * q[8] - q[9];
      const double e20 = 3 * q[0] - 2 * q[3] + q[4], e21 = -3 * q[0] + 2 * q[3] - q[4] + q[5] + q[8] - q[9];
      const double e30 = -q[0] + q[1] + q[3] - q[4];
      double cubic_terms[4];
      for (int k = 0; k < 4; ++k) cubic_terms[k] = e30 * S3[k] + e21 * S2T[k] + e12 * ST2[k] + e03 * T3[k];
      double* w = power[c];
      w[0] = cubic_terms[0], w[2] = cubic_terms[1], w[5] = cubic_terms[2], w[9] = cubic_terms[3];
      w[1] = e20 * S2[0] + e11 * ST[0] + e02 * T2[0];
      w[4] = e20 * S2[1] + e11 * ST[1] + e02 * T2[1];
      w[8] = e20 * S2[2] + e11 * ST[2] + e02 * T2[2];
      w[3] = e10 * a + e01 * c_, w[7] = e10 * b_ + e01 * d;
      w[6] = q[0];
    }
    by_power = true;
  }
  // Cubic by the power form: pixels xs..xe of row y, two at a time.
  void power_row(int y, int xs, int xe, float* px) const {
    const double Y = y - p0.y;
    // The row's cubic in X by channel, in both lanes.
    v2d a0[max_channels], a1[max_channels], a2[max_channels], a3[max_channels];
    for (int c = 0; c < C; ++c) {
      const double* w = power[c];
      const double k2 = w[1] + w[2] * Y, k1 = w[3] + (w[4] + w[5] * Y) * Y, k0 = w[6] + (w[7] + (w[8] + w[9] * Y) * Y) * Y;
      a3[c] = v2d{w[0], w[0]}, a2[c] = v2d{k2, k2}, a1[c] = v2d{k1, k1}, a0[c] = v2d{k0, k0};
    }
    // Pixels x and x + 1 at `at`; an odd last pixel is a pair's first lane.
    auto pixels = [&](int x, float* at, bool both) {
      const v2d X = v2d{double(x), double(x + 1)} - p0.x;
      for (int c = 0; c < C; ++c) {
        const v2d r = clamp_pair(((a3[c] * X + a2[c]) * X + a1[c]) * X + a0[c], c);
        at[c] = static_cast<float>(r[0]);
        if (both) at[C + c] = static_cast<float>(r[1]);
      }
    };
    int x = xs;
    for (; x < xe; x += 2, px += 2 * C) pixels(x, px, true);
    if (x == xe) pixels(x, px, false);
  }
  // std::clamp(v, lo[c], hi[c]) in both lanes (v < lo ? lo : hi < v ? hi : v),
  // as pixel() does it.
  v2d clamp_pair(v2d v, int c) const {
    const v2d vlo = {lo[c], lo[c]}, vhi = {hi[c], hi[c]};
    const v2d r1 = v < vlo ? vlo : v;
    return vhi < r1 ? vhi : r1;
  }
  // Linear: pixels xs..xe of row Y.
  void row(double Y, int xs, int xe, float* px) const {
    double base[max_channels];
    for (int c = 0; c < C; ++c) base[c] = v0[c] + (Y - p0.y) * sy[c] + (xs - p0.x) * sx[c];
    for (int x = xs; x <= xe; ++x, px += C) {
      const double dx = x - xs;
      for (int c = 0; c < C; ++c) px[c] = static_cast<float>(base[c] + dx * sx[c]);
    }
  }
  // Linear: one pixel as row() draws it, from dy = Y - p0.y, dxs = xs - p0.x
  // and dx = x - xs (the same operations in the same order).
  void placed_pixel(double dy, double dxs, double dx, float* px) const {
    for (int c = 0; c < C; ++c) px[c] = static_cast<float>((v0[c] + dy * sy[c] + dxs * sx[c]) + dx * sx[c]);
  }
  // Cubic: one pixel from its barycentric weights.
  void pixel(double l0, double l1, double l2, float* px) const {
    double m[10];
    bernstein_monomials(l0, l1, l2, m);
    monomial_pixel(m, px);
  }
  // Cubic: one pixel from its monomials m (pixel()'s), clamped.
  void monomial_pixel(const double* m, float* px) const {
    for (int c = 0; c < C; ++c) {
      const double* bc = b[c];
      // A balanced sum: short dependency chains.
      const double v = ((bc[0] * m[0] + bc[1] * m[1]) + (bc[2] * m[2] + bc[3] * m[3])) +
                       ((bc[4] * m[4] + bc[5] * m[5]) + (bc[6] * m[6] + bc[7] * m[7])) + (bc[8] * m[8] + bc[9] * m[9]);
      px[c] = static_cast<float>(std::clamp(v, lo[c], hi[c]));
    }
  }
  // Cubic: two pixels at once (at px and qx), lane by lane the same
  // operations in the same order as pixel(), so the same bits.
  void pixel_pair(v2d l0, v2d l1, v2d l2, float* px, float* qx) const {
    v2d m[10];
    bernstein_monomials(l0, l1, l2, m);
    monomial_pair(m, px, qx);
  }
  // Cubic: two pixels from their monomials, lane by lane as monomial_pixel().
  void monomial_pair(const v2d* m, float* px, float* qx) const {
    for (int c = 0; c < C; ++c) {
      const double* bc = b[c];
      const v2d v = ((bc[0] * m[0] + bc[1] * m[1]) + (bc[2] * m[2] + bc[3] * m[3])) +
                    ((bc[4] * m[4] + bc[5] * m[5]) + (bc[6] * m[6] + bc[7] * m[7])) + (bc[8] * m[8] + bc[9] * m[9]);
      const v2d r = clamp_pair(v, c);
      px[c] = static_cast<float>(r[0]);
      qx[c] = static_cast<float>(r[1]);
    }
  }
};

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
void trace_walks(const Scene& scene, Walk* walks, int n, index_t stop_below) {
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
// pixel at most once. Adds the pixels and pieces drawn to counts; on
// return, row r's pixels drawn are [first[r], left[r]).
template <int CT, bool cubic>
void draw_walk(const Scene& scene, const Walk& walk, int m, int shift, Image& out, std::vector<int>& first,
               std::vector<int>& left, std::vector<int>& right, DrawCounts& counts) {
  const int W = out.width, g = walk.g;
  first.resize(m), left.resize(m), right.resize(m);
  {
    const index_t a = scene.tail(walk.start), b = scene.tail(next_edge(walk.start));
    const Crossing boundary(scene.pos(b), scene.pos(a), scene.exact(a) && scene.exact(b));
    boundary.first_right(g, m, W, left.data());
    first = left;
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

// Lattice meshes: every vertex at the same fractional position in output
// pixels (pixel centres at integer scales), so the triangles are copies of
// a few shapes moved by whole pixels, and with exact coordinates so are the
// pixels they own. A shape's pixels are found once, by the walk's own
// crossings (first_right, exact and shift-invariant), and each copy draws
// from the list: no walk, no crossings, and for the linear render no rows
// (a flat loop; small scales are bound by the work per triangle and row).
// Same pixels, same values bit for bit; the rim is still walked.
// Shapes pay where triangles own few pixels. At large scales the walk's
// order (a group of rows at a time, left to right) keeps the rows' cache
// lines and wins. Measured on lenna, one thread, by shape against walked:
// linear x2 0.021 s against 0.034, x4 0.027 against 0.051, x10 0.078
// against 0.093, but x20 0.226 against 0.201; cubic x1 0.029 against
// 0.037, x4 0.075 against 0.089, x6 0.111 against 0.125, x7 even, x8
// 0.167 against 0.155, x10 0.222 against 0.195.
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

// A lattice triangle's offsets in whole output pixels: d1 = p1 - p0 and
// d2 = p2 - p0 (exact integers on a lattice).
void shape_offsets(const Point2 p[3], int d1[2], int d2[2]) {
  d1[0] = static_cast<int>(p[1].x - p[0].x), d1[1] = static_cast<int>(p[1].y - p[0].y);
  d2[0] = static_cast<int>(p[2].x - p[0].x), d2[1] = static_cast<int>(p[2].y - p[0].y);
}

// The offsets packed in 16 bits each (unique for offsets below 2^15).
std::uint64_t shape_key(const int d1[2], const int d2[2]) {
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
  const Shape* find(const int d1[2], const int d2[2], const Point2& phase) {
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
bool shapes_repeat(const Scene& scene) {
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

}  // namespace

void render_mesh_into(Image& out, int out_row, const Mesh2& mesh, const std::vector<float>& values, int C,
                      const RenderGrid& grid, RenderStats* stats, bool fill_outside, const std::vector<float>* gradients,
                      Progress* progress) {
  if (gradients && (gradients->size() != values.size() * 2 || C > max_channels))
    throw Error("render_mesh: cubic mode needs #V x C x 2 gradients and at most 16 channels");
  if (C > max_channels) throw Error("render_mesh: at most 16 channels");
  RenderStats local;
  const int row0 = grid.rows < 0 ? 0 : std::clamp(grid.first_row, 0, grid.height);
  const int row1 = grid.rows < 0 ? grid.height : std::clamp(grid.first_row + grid.rows, row0, grid.height);
  if (out.width != grid.width || out.channels != C || out_row < 0 || out_row + (row1 - row0) > out.height)
    throw Error("render_mesh_into: the image does not hold the rows");
  if (mesh.triangle_count() == 0) {
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
  scene.V = static_cast<index_t>(mesh.points.size());
  scene.T = mesh.triangle_count();
  bool every_point_used = false;
  scene.hull = hull_half_edges(mesh, &every_point_used);
  if (fill_outside) add_rim(scene);
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

  constexpr index_t shape_chunk = 1 << 12;  // triangles
  const int shape_chunks = by_shape ? static_cast<int>((scene.T + shape_chunk - 1) / shape_chunk) : 0;
  std::optional<ShapeTable> shapes;  // 256 KB of slots: only when used
  if (by_shape) shapes.emplace(static_cast<std::ptrdiff_t>(grid.width) * C, C, gradients != nullptr);
  if (progress) progress->begin("render", groups + shape_chunks);
  std::atomic<long long> drawn{0}, overlap{0}, power_pieces{0}, bernstein_pieces{0}, shaped{0};
  auto draw_groups = [&](auto channels, auto cubic) {
    constexpr int CT = decltype(channels)::value;
    constexpr bool is_cubic = decltype(cubic)::value;
    tbb::parallel_for(tbb::blocked_range<int>(0, groups), [&](const tbb::blocked_range<int>& range) {
      std::vector<int> first, left, right;
      Walk walks[walk_batch];
      int walk_group[walk_batch];
      // Spans of a group's walks when it has several (a non-convex boundary):
      // (group, row, first pixel, end).
      std::vector<std::array<int, 4>> extents;
      DrawCounts counts;
      long long twice = 0;
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
          draw_walk<CT, is_cubic>(scene, walks[j], m, shift, out, first, left, right, counts);
          if (starts_of[k + 1] - starts_of[k] > 1)
            for (int r = 0; r < m; ++r) extents.push_back({k, r, first[r], left[r]});
        }
      }
      // Walks from different starts meet only if the boundary is inconsistent.
      std::sort(extents.begin(), extents.end());
      for (std::size_t i = 0, j = 0; i < extents.size(); i = j) {  // per (group, row): overlaps with the spans before
        int reach = extents[i][3];
        for (j = i + 1; j < extents.size() && extents[j][0] == extents[i][0] && extents[j][1] == extents[i][1]; ++j) {
          twice += std::max(0, std::min(reach, extents[j][3]) - extents[j][2]);
          reach = std::max(reach, extents[j][3]);
        }
      }
      drawn += counts.pixels, overlap += twice;
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
  local.overcovered = overlap;
  local.power_pieces = power_pieces, local.bernstein_pieces = bernstein_pieces;
  local.shaped_triangles = shaped;
  local.shapes = shapes ? static_cast<long long>(shapes->size()) : 0;
  local.uncovered = static_cast<long long>(rows) * grid.width - (drawn - overlap);

  // Samples that fall on pixel centres are written exactly (the plane and
  // the patch equal the vertex value there up to rounding).
  std::vector<char> used;
  if (!every_point_used) {
    used.assign(scene.V, 0);
    for (index_t v : mesh.tri) used[v] = 1;
  }
  tbb::parallel_for(index_t(0), scene.V, [&](index_t v) {
    if (!used.empty() && !used[v]) return;
    const Point2 p = scene.pos(v);
    if (p.x != std::floor(p.x) || p.y != std::floor(p.y)) return;
    if (p.x < 0 || p.y < row0 || p.x >= grid.width || p.y >= row1) return;
    const float* z = scene.value(v);
    float* px = &out.pixels[out.index(static_cast<int>(p.x), static_cast<int>(p.y) - shift)];
    for (int c = 0; c < C; ++c) px[c] = z[c];
  });

  if (stats) *stats = local;
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
