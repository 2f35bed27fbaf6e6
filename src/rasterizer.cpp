#include "rasterizer.hpp"

#include "cubic_surface.hpp"
#include "error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <type_traits>

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

// Two doubles, one SSE2 register: element-wise IEEE operations.
typedef double v2d __attribute__((vector_size(16)));

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

  // Set up when the triangle turns out to own a pixel (many own none at
  // small scales).
  void init(const Scene& scene, index_t t, const index_t id[3], const Point2& q0, const Point2& p1, const Point2& p2,
            double area2) {
    C = CT > 0 ? CT : scene.C, p0 = q0, inv_area2 = 1.0 / area2;
    const float *z0 = scene.value(id[0]), *z1 = scene.value(id[1]), *z2 = scene.value(id[2]);
    const double ux = p1.x - p0.x, uy = p1.y - p0.y, vx = p2.x - p0.x, vy = p2.y - p0.y;
    if constexpr (cubic) {
      if (t < scene.T) {
        mesh_patches(scene, id);
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
  // Linear: pixels xs..xe of row Y.
  void row(double Y, int xs, int xe, float* px) const {
    double base[max_channels];
    for (int c = 0; c < C; ++c) base[c] = v0[c] + (Y - p0.y) * sy[c] + (xs - p0.x) * sx[c];
    for (int x = xs; x <= xe; ++x, px += C) {
      const double dx = x - xs;
      for (int c = 0; c < C; ++c) px[c] = static_cast<float>(base[c] + dx * sx[c]);
    }
  }
  // Cubic: one pixel from its barycentric weights.
  void pixel(double l0, double l1, double l2, float* px) const {
    const double l00 = l0 * l0, l11 = l1 * l1, l22 = l2 * l2;
    const double m[10] = {l00 * l0, l11 * l1, l22 * l2, l00 * l1, l0 * l11, l11 * l2, l1 * l22, l0 * l22, l00 * l2,
                          l0 * l1 * l2};
    for (int c = 0; c < C; ++c) {
      const double* bc = b[c];
      // A balanced sum: short dependency chains.
      const double v = ((bc[0] * m[0] + bc[1] * m[1]) + (bc[2] * m[2] + bc[3] * m[3])) +
                       ((bc[4] * m[4] + bc[5] * m[5]) + (bc[6] * m[6] + bc[7] * m[7])) + (bc[8] * m[8] + bc[9] * m[9]);
      px[c] = static_cast<float>(std::clamp(v, lo[c], hi[c]));
    }
  }
  // Cubic: two neighbouring pixels at once (px and px + C), lane by lane
  // the same operations in the same order as pixel(), so the same bits.
  void pixel_pair(v2d l0, v2d l1, v2d l2, float* px) const {
    const v2d l00 = l0 * l0, l11 = l1 * l1, l22 = l2 * l2;
    const v2d m[10] = {l00 * l0, l11 * l1, l22 * l2, l00 * l1, l0 * l11, l11 * l2, l1 * l22, l0 * l22, l00 * l2,
                       l0 * l1 * l2};
    for (int c = 0; c < C; ++c) {
      const double* bc = b[c];
      const v2d v = ((bc[0] * m[0] + bc[1] * m[1]) + (bc[2] * m[2] + bc[3] * m[3])) +
                    ((bc[4] * m[4] + bc[5] * m[5]) + (bc[6] * m[6] + bc[7] * m[7])) + (bc[8] * m[8] + bc[9] * m[9]);
      // std::clamp(v, lo, hi): v < lo ? lo : hi < v ? hi : v
      const v2d vlo = {lo[c], lo[c]}, vhi = {hi[c], hi[c]};
      const v2d r1 = v < vlo ? vlo : v;
      const v2d r = vhi < r1 ? vhi : r1;
      px[c] = static_cast<float>(r[0]);
      px[C + c] = static_cast<float>(r[1]);
    }
  }
};

inline void count_hits(unsigned char* h, int xs, int xe) {
  for (int x = xs; x <= xe; ++x) h[x] = static_cast<unsigned char>(h[x] < 255 ? h[x] + 1 : 255);
}

// Draws the part of triangle t on grid rows [row_begin, row_end) into `out`,
// grid row y to out row y - row0; hits counts the band's pixels.
template <int CT, bool cubic>
void draw_triangle(const Scene& scene, index_t t, int row_begin, int row_end, int row0, Image& out,
                   unsigned char* hits) {
  index_t id[3];
  scene.corners(t, id);
  const Point2 p0 = scene.pos(id[0]), p1 = scene.pos(id[1]), p2 = scene.pos(id[2]);
  const double min_y = std::min({p0.y, p1.y, p2.y}), max_y = std::max({p0.y, p1.y, p2.y});
  const int y_lo = std::max(row_begin, ceil_int(clamp_pixels(min_y)));
  const int y_hi = std::min(row_end - 1, floor_int(clamp_pixels(max_y)));
  if (y_lo > y_hi) return;
  const bool exact = t < scene.T ? scene.mesh_exact : scene.exact(id[0]) && scene.exact(id[1]) && scene.exact(id[2]);
  const double area2 = (p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x);
  // Collapsed by the output transform: nothing to own.
  if (exact ? !(area2 > 0) : orientation(p0, p1, p2) <= 0) return;
  const int W = out.width;
  const double min_x = std::min({p0.x, p1.x, p2.x}), max_x = std::max({p0.x, p1.x, p2.x});
  const int x_min = std::max(0, ceil_int(clamp_pixels(min_x)));
  const int x_max = std::min(W - 1, floor_int(clamp_pixels(max_x)));
  if (x_min > x_max) return;
  Shader<CT, cubic> shader;
  bool shader_ready = false;
  auto ready = [&]() -> const Shader<CT, cubic>& {
    if (!shader_ready) shader.init(scene, t, id, p0, p1, p2, area2), shader_ready = true;
    return shader;
  };
  const int C = CT > 0 ? CT : scene.C;
  const Point2* P[3] = {&p0, &p1, &p2};

  if (exact) {
    // Exact coordinates: the edge functions E_k of edges p_k -> p_(k+1),
    // stepped from pixel to pixel, exactly (each value is an edge function
    // at a pixel centre: a multiple of 2^-20 below 2^33). A centre is
    // inside edge k when E_k > 0, or E_k == 0 and the tie goes to this
    // side; E_k > -2^-21 says both. E_k / area2 is the barycentric weight
    // of the vertex opposite the edge.
    double row_start[3], step_x[3], step_y[3], threshold[3];
    for (int k = 0; k < 3; ++k) {
      const Point2 &u = *P[k], &v = *P[(k + 1) % 3];
      row_start[k] = (v.x - u.x) * (y_lo - u.y) - (v.y - u.y) * (x_min - u.x);
      step_x[k] = -(v.y - u.y);
      step_y[k] = v.x - u.x;
      threshold[k] = tie_side(u, v) > 0 ? -0x1p-21 : 0.0;
    }
    auto inside = [&](const double e[3]) {
      return (e[0] > threshold[0]) & (e[1] > threshold[1]) & (e[2] > threshold[2]);
    };
    for (int y = y_lo; y <= y_hi; ++y) {
      double e[3] = {row_start[0], row_start[1], row_start[2]};
      for (int k = 0; k < 3; ++k) row_start[k] += step_y[k];
      int x = x_min;
      while (x <= x_max && !inside(e)) {
        ++x;
        for (int k = 0; k < 3; ++k) e[k] += step_x[k];
      }
      if (x > x_max) continue;
      const int xs = x;
      float* px = &out.pixels[out.index(xs, y - row0)];
      ready();
      if constexpr (cubic) {
        // The span first, then its pixels in pairs; e at pixel x is
        // exactly e at xs plus (x - xs) steps (all exact values).
        const double es[3] = {e[0], e[1], e[2]};
        while (x <= x_max && inside(e)) {
          ++x;
          for (int k = 0; k < 3; ++k) e[k] += step_x[k];
        }
        const int xe = x - 1;
        const double inv = shader.inv_area2;
        v2d ev[3], step2[3];
        for (int k = 0; k < 3; ++k) ev[k] = v2d{es[k], es[k] + step_x[k]}, step2[k] = v2d{2 * step_x[k], 2 * step_x[k]};
        const v2d vinv = {inv, inv};
        int xp = xs;
        for (; xp + 1 <= xe; xp += 2, px += 2 * C) {
          shader.pixel_pair(ev[1] * vinv, ev[2] * vinv, ev[0] * vinv, px);
          for (int k = 0; k < 3; ++k) ev[k] += step2[k];
        }
        if (xp == xe) shader.pixel(ev[1][0] * inv, ev[2][0] * inv, ev[0][0] * inv, px);
        x = xe + 1;
      } else {
        while (x <= x_max && inside(e)) {
          ++x;
          for (int k = 0; k < 3; ++k) e[k] += step_x[k];
        }
        shader.row(y, xs, x - 1, px);
      }
      count_hits(hits + static_cast<std::size_t>(y - row_begin) * W, xs, x - 1);
    }
    return;
  }

  // General coordinates: per row, the crossing of each edge in floating
  // point (accurate far below a pixel), then the exact side at the pixels
  // next to it decides the integer bound.
  Edge edges[3];
  double slope[3];  // dX/dY along each non-horizontal edge
  for (int k = 0; k < 3; ++k) {
    const Point2 &u = *P[k], &v = *P[(k + 1) % 3];
    edges[k] = Edge{u, v, v.x - u.x, v.y - u.y, tie_side(u, v), false};
    slope[k] = edges[k].beta != 0 ? edges[k].alpha / edges[k].beta : 0;
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
      const double cross = std::clamp(ed.u.x + (Y - ed.u.y) * slope[k], double(x_min) - 1, double(x_max) + 1);
      if (ed.beta > 0) {  // inside for X left of the crossing: a right bound
        int x = std::min(xe, floor_int(cross));
        while (x + 1 <= xe && ed.side(x + 1, Y) > 0) ++x;
        while (x >= xs && ed.side(x, Y) < 0) --x;
        xe = x;
      } else {  // a left bound
        int x = std::max(xs, ceil_int(cross));
        while (x - 1 >= xs && ed.side(x - 1, Y) > 0) --x;
        while (x <= xe && ed.side(x, Y) < 0) ++x;
        xs = x;
      }
    }
    if (xs > xe) continue;
    float* px = &out.pixels[out.index(xs, y - row0)];
    ready();
    if constexpr (cubic) {
      // Weights from the edge functions of p1->p2 and p2->p0 (of p0 and p1).
      const Point2 &a = p1, &b = p2;
      for (int x = xs; x <= xe; ++x, px += C) {
        const double l0 = ((b.x - a.x) * (Y - a.y) - (b.y - a.y) * (x - a.x)) * shader.inv_area2;
        const double l1 = ((p0.x - b.x) * (Y - b.y) - (p0.y - b.y) * (x - b.x)) * shader.inv_area2;
        shader.pixel(l0, l1, 1.0 - l0 - l1, px);
      }
    } else {
      shader.row(Y, xs, xe, px);
    }
    count_hits(hits + static_cast<std::size_t>(y - row_begin) * W, xs, xe);
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

// Rows [first, last] (clipped to [row0, row1)) a triangle may own; first >
// last when none.
void row_range(const Scene& scene, index_t t, int row0, int row1, int& first, int& last) {
  index_t id[3];
  scene.corners(t, id);
  const double y0 = scene.pos(id[0]).y, y1 = scene.pos(id[1]).y, y2 = scene.pos(id[2]).y;
  const double lo = std::min({y0, y1, y2}), hi = std::max({y0, y1, y2});
  first = std::max(row0, ceil_int(clamp_pixels(lo)));
  last = std::min(row1 - 1, floor_int(clamp_pixels(hi)));
}

}  // namespace

void render_mesh_into(Image& out, int out_row, const Mesh2& mesh, const std::vector<float>& values, int C,
                      const RenderGrid& grid, RenderStats* stats, bool fill_outside, const std::vector<float>* gradients,
                      Progress* progress) {
  if (gradients && (gradients->size() != values.size() * 2 || C > max_channels))
    throw Error("render_mesh: cubic mode needs #V x C x 2 gradients and at most 16 channels");
  if (C > max_channels) throw Error("render_mesh: at most 16 channels");
  if (grid.height > band_rows * 65535) throw Error("render_mesh: the output is too tall");
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
  if (fill_outside) add_rim(scene);
  local.triangles = scene.T;
  local.rim_triangles = static_cast<long long>(scene.rim_tris.size() / 3);
  std::atomic<bool> exact{grid.width <= 32768 && grid.height <= 32768};
  tbb::parallel_for(tbb::blocked_range<index_t>(0, scene.V, 1 << 16), [&](const tbb::blocked_range<index_t>& r) {
    for (index_t v = r.begin(); v < r.end() && exact.load(std::memory_order_relaxed); ++v) {
      const Point2 p = scene.pos(v);
      if (!exact_coordinate(p.x) || !exact_coordinate(p.y)) exact = false;
    }
  });
  scene.mesh_exact = exact;
  scene.rim_exact.resize(scene.rim_points.size());
  for (std::size_t i = 0; i < scene.rim_points.size(); ++i) {
    const Point2 p = scene.pos(scene.V + static_cast<index_t>(i));
    scene.rim_exact[i] = scene.mesh_exact && exact_coordinate(p.x) && exact_coordinate(p.y);
  }

  // Bin triangles by bands of rows; bands are drawn in parallel and own
  // their pixels, so no two threads write the same pixel. Runs of
  // `run_size` consecutive triangles that span at most two bands (a mesh in
  // spatial order, as an image's: triangles by smallest vertex id) are
  // binned whole, and each band draws a run's triangles that reach it; the
  // triangles of the other runs (the rim, meshes in no spatial order) are
  // binned one by one (a counting sort over fixed chunks of triangles).
  const int bands = (row1 - row0 + band_rows - 1) / band_rows;
  const index_t n_tris = scene.triangle_count();
  constexpr index_t run_size = 256;
  const index_t n_runs = (n_tris + run_size - 1) / run_size;
  auto band_span = [&](index_t t, int& b0, int& b1) {  // b0 > b1: none
    int first, last;
    row_range(scene, t, row0, row1, first, last);
    b0 = first <= last ? (first - row0) / band_rows : 1, b1 = first <= last ? (last - row0) / band_rows : 0;
  };
  std::vector<std::uint32_t> run_span(n_runs);  // first band | last band << 16; first > last: none
  tbb::parallel_for(tbb::blocked_range<index_t>(0, n_runs, 64), [&](const tbb::blocked_range<index_t>& r) {
    for (index_t k = r.begin(); k < r.end(); ++k) {
      int lo = bands, hi = -1;
      for (index_t t = k * run_size; t < std::min(n_tris, (k + 1) * run_size); ++t) {
        int b0, b1;
        band_span(t, b0, b1);
        if (b0 <= b1) lo = std::min(lo, b0), hi = std::max(hi, b1);
      }
      run_span[k] = lo <= hi ? static_cast<std::uint32_t>(lo) | static_cast<std::uint32_t>(hi) << 16 : 1u;
    }
  });
  auto run_first = [&](index_t k) { return static_cast<int>(run_span[k] & 0xffff); };
  auto run_last = [&](index_t k) { return static_cast<int>(run_span[k] >> 16); };
  auto whole = [&](index_t k) { return run_last(k) - run_first(k) <= 1; };  // also true for empty runs
  // Runs binned whole: band-major lists.
  std::vector<index_t> run_offset(bands + 1, 0), runs_binned;
  for (index_t k = 0; k < n_runs; ++k)
    if (whole(k))
      for (int b = run_first(k); b <= run_last(k); ++b) ++run_offset[b + 1];
  for (int b = 0; b < bands; ++b) run_offset[b + 1] += run_offset[b];
  runs_binned.resize(run_offset[bands]);
  {
    std::vector<index_t> cursor(run_offset.begin(), run_offset.end() - 1);
    for (index_t k = 0; k < n_runs; ++k)
      if (whole(k))
        for (int b = run_first(k); b <= run_last(k); ++b) runs_binned[cursor[b]++] = k;
  }
  // The other triangles, one by one.
  const index_t chunk = std::max<index_t>(1 << 14, (n_tris / 256 + run_size) / run_size * run_size);  // runs whole
  const int chunks = static_cast<int>((n_tris + chunk - 1) / chunk);
  std::vector<std::size_t> offset(static_cast<std::size_t>(chunks) * bands + 1, 0);  // [band][chunk]: count, then start
  auto slot = [&](int k, int b) -> std::size_t& { return offset[static_cast<std::size_t>(b) * chunks + k]; };
  auto for_each_single = [&](int k, auto&& f) {  // the triangles of chunk k not in whole runs, with their bands
    for (index_t t = k * chunk; t < std::min(n_tris, (k + 1) * chunk); t += run_size) {
      if (whole(t / run_size)) continue;
      for (index_t u = t; u < std::min(n_tris, t + run_size); ++u) {
        int b0, b1;
        band_span(u, b0, b1);
        for (int b = b0; b <= b1; ++b) f(u, b);
      }
    }
  };
  tbb::parallel_for(0, chunks, [&](int k) { for_each_single(k, [&](index_t, int b) { ++slot(k, b); }); });
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
    for_each_single(k, [&](index_t t, int b) { binned[cursor[b]++] = t; });
  });
  auto band_begin = [&](int b) { return offset[static_cast<std::size_t>(b) * chunks]; };
  auto band_end = [&](int b) { return b + 1 < bands ? offset[static_cast<std::size_t>(b + 1) * chunks] : running; };

  if (progress) progress->begin("render", bands);
  std::vector<long long> band_uncovered(bands, 0), band_overcovered(bands, 0);
  std::vector<std::vector<std::pair<int, int>>> holes(bands);  // uncovered pixels (x, y)
  auto draw = [&](index_t t, int row_begin, int row_end, unsigned char* hits) {
    auto with = [&](auto channels, auto cubic) {
      draw_triangle<decltype(channels)::value, decltype(cubic)::value>(scene, t, row_begin, row_end, shift, out, hits);
    };
    const bool cubic = gradients != nullptr;
    switch (C) {
      case 1: return cubic ? with(channels<1>{}, std::true_type{}) : with(channels<1>{}, std::false_type{});
      case 3: return cubic ? with(channels<3>{}, std::true_type{}) : with(channels<3>{}, std::false_type{});
      case 4: return cubic ? with(channels<4>{}, std::true_type{}) : with(channels<4>{}, std::false_type{});
      default: return cubic ? with(channels<0>{}, std::true_type{}) : with(channels<0>{}, std::false_type{});
    }
  };
  // One coverage buffer per task, reused by its bands (no fresh pages per band).
  tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const tbb::blocked_range<int>& range) {
   std::vector<unsigned char> hits;
   for (int b = range.begin(); b < range.end(); ++b) {
    const int row_begin = row0 + b * band_rows, row_end = std::min(row1, row_begin + band_rows);
    hits.assign(static_cast<std::size_t>(row_end - row_begin) * grid.width, 0);
    for (index_t i = run_offset[b]; i < run_offset[b + 1]; ++i) {
      const index_t k = runs_binned[i];
      for (index_t t = k * run_size; t < std::min(n_tris, (k + 1) * run_size); ++t)
        draw(t, row_begin, row_end, hits.data());
    }
    for (std::size_t i = band_begin(b); i < band_end(b); ++i) draw(binned[i], row_begin, row_end, hits.data());
    int zero = 0, many = 0;  // a band has fewer than 2^31 pixels
    for (const unsigned char h : hits) {
      zero += h == 0;
      many += h > 1;
    }
    band_uncovered[b] = zero, band_overcovered[b] = many;
    if (zero > 0 && fill_outside)
      for (std::size_t i = 0; i < hits.size(); ++i)
        if (hits[i] == 0)
          holes[b].emplace_back(static_cast<int>(i % grid.width), row_begin - shift + static_cast<int>(i / grid.width));
    if (progress) progress->add(1);
   }
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
    float* px = &out.pixels[out.index(static_cast<int>(p.x), static_cast<int>(p.y) - shift)];
    for (int c = 0; c < C; ++c) px[c] = z[c];
  });

  if (fill_outside && local.uncovered > 0) {
    // Only slivers collapsed by rounding can leave a hole; copy a neighbour
    // (in raster order, so a filled hole can feed the next).
    for (const auto& band : holes)
      for (auto [x, y] : band) {
        const int sx = x > 0 ? x - 1 : std::min(x + 1, grid.width - 1);
        const int sy = x > 0 || grid.width > 1 ? y : (y > out_row ? y - 1 : std::min(y + 1, out_row + row1 - row0 - 1));
        for (int c = 0; c < C; ++c) out.at(x, y, c) = out.at(sx, sy, c);
      }
  }
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
