// The rim: slabs per hull edge and fans per hull corner outside the mesh,
// so one drawing path also covers the outside (image/rasterizer.hpp).
#include "image/raster/scene.hpp"

#include "image/cubic_surface.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ddt::raster {

// Adds the slabs and corner fans that extend the hull's values outward.
// Built in input coordinates (distances there define "nearest"), far enough
// that the output domain is covered.
void add_rim(SceneGeometry& scene) {
  const Mesh2& mesh = scene.mesh;
  const RenderGrid& grid = scene.grid;
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
      add_triangle(v, previous, next_far);  // the fan's value: v's, as make_rim_patches reads it
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

std::vector<std::array<double, 10>> make_rim_patches(const Scene& scene) {
  const SceneGeometry& geometry = scene.geometry;
  const Mesh2& mesh = scene.mesh;
  const std::vector<float>& values = scene.values;
  const int C = scene.C;
  const std::size_t slabs = 2 * geometry.hull.size(), triangles = geometry.rim_tris.size() / 3;
  std::vector<std::array<double, 10>> patches;
  patches.reserve(triangles * C);
  // Slabs: hull edge k's are rim triangles 2k (v, u, Fu) and 2k + 1 (v, Fu,
  // Fv), whose value is the hull edge's cubic at the nearest edge point, a
  // function of t, the position along u->v: t = l0 in the first, l0 + l2
  // in the second. A Bézier triangle of a function of l0 (+ l2) has
  // control value d[i] (d[i + k]) at index ijk.
  const VertexValues* window = scene.gradient_window;
  for (const index_t e : geometry.hull) {
    const index_t u = mesh.tri[e], v = mesh.tri[next_edge(e)];
    const Point2 &pu = mesh.points[u], &pv = mesh.points[v];
    if (window && (std::min(u, v) < window->first || std::max(u, v) >= window->end)) {
      // Beyond the window of gradients: not drawn by this call (scene_patch refuses it).
      std::array<double, 10> unknown;
      unknown.fill(std::numeric_limits<double>::quiet_NaN());
      patches.insert(patches.end(), 2 * static_cast<std::size_t>(C), unknown);
      continue;
    }
    for (int pass = 0; pass < 2; ++pass)
      for (int c = 0; c < C; ++c) {
        const float* gu = scene.gradient(u) + 2 * c;
        const float* gv = scene.gradient(v) + 2 * c;
        const double dx = pv.x - pu.x, dy = pv.y - pu.y;
        const double zu = values[static_cast<std::size_t>(u) * C + c], zv = values[static_cast<std::size_t>(v) * C + c];
        const double d[4] = {zu, zu + (gu[0] * dx + gu[1] * dy) / 3, zv - (gv[0] * dx + gv[1] * dy) / 3, zv};
        // order: 300, 030, 003, 210, 120, 021, 012, 102, 201, 111 as (i, k) of l0, l2 powers
        const int ik[10][2] = {{3, 0}, {0, 0}, {0, 3}, {2, 0}, {1, 0}, {0, 1}, {0, 2}, {1, 2}, {2, 1}, {1, 1}};
        std::array<double, 10> b;
        for (int q = 0; q < 10; ++q) b[q] = d[pass == 0 ? ik[q][0] : ik[q][0] + ik[q][1]];
        patches.push_back(b);
      }
  }
  // Fans: constant, the value of their first corner (the hull vertex).
  for (std::size_t t = slabs; t < triangles; ++t)
    for (int c = 0; c < C; ++c) {
      std::array<double, 10> b;
      b.fill(values[static_cast<std::size_t>(geometry.rim_tris[3 * t]) * C + c]);
      patches.push_back(b);
    }
  return patches;
}

std::array<double, 10> scene_patch(const Scene& scene, index_t t, const index_t i[3], int c) {
  const int C = scene.C;
  if (t >= scene.T) {
    const std::array<double, 10>& patch = scene.rim_patches[static_cast<std::size_t>(t - scene.T) * C + c];
    if (scene.gradient_window && std::isnan(patch[0]))  // values are finite (the readers refuse others)
      throw Error("render_mesh: a rim patch beyond the window of gradients");
    return patch;
  }
  const auto& P = scene.mesh.points;
  auto grad = [&](index_t v) { return scene.gradient(v) + 2 * c; };
  double g0[2] = {grad(i[0])[0], grad(i[0])[1]}, g1[2] = {grad(i[1])[0], grad(i[1])[1]},
         g2[2] = {grad(i[2])[0], grad(i[2])[1]};
  return cubic_patch(P[i[0]], P[i[1]], P[i[2]], scene.values[static_cast<std::size_t>(i[0]) * C + c],
                     scene.values[static_cast<std::size_t>(i[1]) * C + c],
                     scene.values[static_cast<std::size_t>(i[2]) * C + c], g0, g1, g2);
}

}  // namespace ddt::raster
