#include "optimizer.hpp"

#include "error.hpp"

#include <cmath>

namespace ddt {
namespace {

// Per-channel gradients of the linear interpolant on one triangle, and its area.
struct TriangleField {
  bool present = false;
  index_t ids[3] = {0, 0, 0};
  double area = 0;
  double grad[max_cost_channels][2];
};

TriangleField triangle_field(const Mesh2& mesh, const std::vector<float>& values, int K, index_t i0, index_t i1,
                             index_t i2) {
  TriangleField t;
  t.present = true;
  t.ids[0] = i0, t.ids[1] = i1, t.ids[2] = i2;
  const Point2 &p0 = mesh.points[i0], &p1 = mesh.points[i1], &p2 = mesh.points[i2];
  const double ux = p1.x - p0.x, uy = p1.y - p0.y, vx = p2.x - p0.x, vy = p2.y - p0.y;
  const double det = ux * vy - uy * vx;
  t.area = 0.5 * std::abs(det);
  const double inv = 1.0 / det;
  const float *z0 = &values[static_cast<std::size_t>(i0) * K], *z1 = &values[static_cast<std::size_t>(i1) * K],
              *z2 = &values[static_cast<std::size_t>(i2) * K];
  for (int k = 0; k < K; ++k) {
    const double d1 = double(z1[k]) - z0[k], d2 = double(z2[k]) - z0[k];
    t.grad[k][0] = (d1 * vy - d2 * uy) * inv;
    t.grad[k][1] = (d2 * ux - d1 * vx) * inv;
  }
  return t;
}

// The triangle across half-edge h (the one owning opp[h]), or absent on the hull.
TriangleField across(const Mesh2& mesh, const std::vector<float>& values, int K, index_t h) {
  const index_t o = mesh.opp[h];
  if (o == no_edge) return {};
  const index_t t = tri_of(o);
  return triangle_field(mesh, values, K, mesh.tri[3 * t], mesh.tri[3 * t + 1], mesh.tri[3 * t + 2]);
}

// The vertex of t that is neither u nor v.
index_t apex_of(const TriangleField& t, index_t u, index_t v) {
  for (index_t id : t.ids)
    if (id != u && id != v) return id;
  return t.ids[0];
}

// Facet cost of edge u-v between triangles s and t (0 on the hull), times
// (area(s) + area(t)) / 3 in the weighted-content form.
double edge_cost(const Mesh2& mesh, const std::vector<float>& values, const CostFunction& cost, int K,
                 const TriangleField& s, const TriangleField& t, index_t u, index_t v) {
  if (!s.present || !t.present) return 0;  // hull edges contribute nothing
  FacetPair facet;
  facet.dim = 2;
  const index_t a1 = apex_of(s, u, v), a2 = apex_of(t, u, v);
  double normal[2], base[2], apex1[2], apex2[2];
  if (cost.facet_geometry) {
    const Point2 &pu = mesh.points[u], &pv = mesh.points[v];
    const Point2 &p1 = mesh.points[a1], &p2 = mesh.points[a2];
    const double len = std::hypot(pv.x - pu.x, pv.y - pu.y);
    normal[0] = -(pv.y - pu.y) / len, normal[1] = (pv.x - pu.x) / len;
    if ((p2.x - pu.x) * normal[0] + (p2.y - pu.y) * normal[1] < 0) normal[0] = -normal[0], normal[1] = -normal[1];
    base[0] = pu.x, base[1] = pu.y, apex1[0] = p1.x, apex1[1] = p1.y, apex2[0] = p2.x, apex2[1] = p2.y;
    facet.normal = normal;
    facet.base = base;
    facet.apex1 = apex1;
    facet.apex2 = apex2;
  }
  double c = 0;
  for (int k = 0; k < K; ++k) {
    facet.g1 = s.grad[k];
    facet.g2 = t.grad[k];
    if (cost.facet_geometry) {
      facet.z_base = values[static_cast<std::size_t>(u) * K + k];
      facet.z_apex1 = values[static_cast<std::size_t>(a1) * K + k];
      facet.z_apex2 = values[static_cast<std::size_t>(a2) * K + k];
    }
    c += cost.facet_cost(facet);
  }
  if (cost.form == CostForm::facet_weighted_content) c *= (s.area + t.area) / 3.0;
  return c;
}

double simplex_cost(const CostFunction& cost, const std::vector<float>& values, int K, const Point2* const p[3],
                    const index_t ids[3]) {
  const double area = 0.5 * std::abs(signed_area2(*p[0], *p[1], *p[2]));
  double w = 0;
  for (int k = 0; k < K; ++k) {
    const double z[3] = {values[static_cast<std::size_t>(ids[0]) * K + k],
                         values[static_cast<std::size_t>(ids[1]) * K + k],
                         values[static_cast<std::size_t>(ids[2]) * K + k]};
    w += cost.simplex_weight(z, 3);
  }
  return area * w;
}

double triangle_cost(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                     index_t a, index_t b, index_t c) {
  const index_t ids[3] = {a, b, c};
  const Point2* p[3] = {&mesh.points[a], &mesh.points[b], &mesh.points[c]};
  return simplex_cost(cost, values, K, p, ids);
}

}  // namespace

double total_cost(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost) {
  double sum = 0;
  if (cost.form == CostForm::simplex_weight) {
    for (index_t t = 0; t < mesh.triangle_count(); ++t)
      sum += triangle_cost(mesh, values, K, cost, mesh.tri[3 * t], mesh.tri[3 * t + 1], mesh.tri[3 * t + 2]);
    return sum;
  }
  for (index_t e = 0; e < mesh.half_edge_count(); ++e) {
    if (mesh.opp[e] == no_edge || mesh.opp[e] < e) continue;
    const index_t s = tri_of(e), t = tri_of(mesh.opp[e]);
    const TriangleField fs = triangle_field(mesh, values, K, mesh.tri[3 * s], mesh.tri[3 * s + 1], mesh.tri[3 * s + 2]);
    const TriangleField ft = triangle_field(mesh, values, K, mesh.tri[3 * t], mesh.tri[3 * t + 1], mesh.tri[3 * t + 2]);
    sum += edge_cost(mesh, values, cost, K, fs, ft, mesh.tri[e], mesh.tri[next_edge(e)]);
  }
  return sum;
}

FlipCosts flip_costs(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                     index_t e) {
  // Names follow the flip diagram in mesh.hpp.
  const index_t f = mesh.opp[e];
  const index_t a = mesh.tri[e], b = mesh.tri[f], c = mesh.tri[prev_edge(e)], d = mesh.tri[prev_edge(f)];
  FlipCosts out;
  if (cost.form == CostForm::simplex_weight) {
    out.before = triangle_cost(mesh, values, K, cost, a, b, c) + triangle_cost(mesh, values, K, cost, b, a, d);
    out.after = triangle_cost(mesh, values, K, cost, d, c, a) + triangle_cost(mesh, values, K, cost, c, d, b);
    return out;
  }
  const TriangleField n_bc = across(mesh, values, K, next_edge(e));
  const TriangleField n_ca = across(mesh, values, K, prev_edge(e));
  const TriangleField n_ad = across(mesh, values, K, next_edge(f));
  const TriangleField n_db = across(mesh, values, K, prev_edge(f));
  const TriangleField t0 = triangle_field(mesh, values, K, a, b, c);
  const TriangleField t1 = triangle_field(mesh, values, K, b, a, d);
  const TriangleField t0n = triangle_field(mesh, values, K, d, c, a);
  const TriangleField t1n = triangle_field(mesh, values, K, c, d, b);
  auto edge = [&](const TriangleField& s, const TriangleField& t, index_t u, index_t v) {
    return edge_cost(mesh, values, cost, K, s, t, u, v);
  };
  out.before = edge(t0, t1, a, b) + edge(t0, n_bc, b, c) + edge(t0, n_ca, c, a) + edge(t1, n_ad, a, d) +
               edge(t1, n_db, d, b);
  out.after = edge(t0n, t1n, c, d) + edge(t1n, n_bc, b, c) + edge(t0n, n_ca, c, a) + edge(t0n, n_ad, a, d) +
              edge(t1n, n_db, d, b);
  return out;
}

LawsonStats optimize_lawson(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                            const LawsonOptions& options) {
  if (K < 1 || K > max_cost_channels)
    throw Error("the cost takes 1 to " + std::to_string(max_cost_channels) + " channels, got " + std::to_string(K));
  LawsonStats stats;
  stats.cost_before = total_cost(mesh, values, K, cost);
  double cost_now = stats.cost_before;

  // pending[h]: slot h is queued (active or candidate) and will be tested.
  // Flips move edges between slots of their two triangles; every edge of
  // those triangles is re-queued, so a stale slot only means an extra test.
  std::vector<char> pending(mesh.half_edge_count(), 0);
  std::vector<index_t> active, candidate;
  for (index_t e = 0; e < mesh.half_edge_count(); ++e)
    if (mesh.opp[e] != no_edge && e < mesh.opp[e]) {
      active.push_back(e);
      pending[e] = 1;
    }
  auto enqueue = [&](index_t h) {
    if (mesh.opp[h] == no_edge || pending[h] || pending[mesh.opp[h]]) return;
    pending[h] = 1;
    candidate.push_back(h);
  };
  const bool reaches_neighbours = cost.form != CostForm::simplex_weight;

  while (!active.empty() && stats.iterations < options.max_iterations) {
    ++stats.iterations;
    long long flips_now = 0;
    for (index_t e : active) {
      pending[e] = 0;
      if (mesh.opp[e] == no_edge) continue;
      ++stats.tests;
      if (!is_flippable(mesh, e)) continue;
      const FlipCosts fc = flip_costs(mesh, values, K, cost, e);
      const double gain = fc.gain();
      if (!(gain > options.relative_tolerance * std::max(fc.before, fc.after)) || gain <= 0) continue;
      const index_t f = mesh.opp[e];
      flip_edge(mesh, e);
      cost_now -= gain;
      ++flips_now;
      for (index_t h : {e, next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)}) enqueue(h);
      if (reaches_neighbours) {
        // Facet costs reach one triangle further: the edges of the four
        // neighbours depend on the gradients of t0 and t1.
        for (index_t h : {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)}) {
          const index_t o = mesh.opp[h];
          if (o == no_edge) continue;
          enqueue(next_edge(o));
          enqueue(prev_edge(o));
        }
      }
    }
    stats.flips += flips_now;
    active.swap(candidate);
    candidate.clear();
    if (options.on_iteration) options.on_iteration(stats.iterations, flips_now, cost_now);
    if (flips_now == 0) break;
  }
  stats.cost_after = total_cost(mesh, values, K, cost);
  return stats;
}

}  // namespace ddt
