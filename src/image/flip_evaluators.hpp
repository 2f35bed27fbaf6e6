#pragma once
// ddt::flip_evaluators — how the 2D optimizer (image/optimizer.cpp) tests a
// flip of half-edge e: the reference (flip_costs, any cost) and the fast
// evaluators of the built-in costs (Sederberg with its region's edge-term
// cache, variance), which decide as the reference bit for bit. Each has
// decide(e, gain, flat, scratch), commit(e, f, scratch) after the flip,
// fill(scratch, first, end) as a region's first phase starts (the sum of
// its terms), and a Scratch a region holds while it runs.

#include "core/costs.hpp"
#include "core/predicates.hpp"
#include "image/mesh.hpp"
#include "image/optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace ddt::flip_evaluators {

// Rotates a counter-clockwise triple to start at its smallest id, so that a
// triangle's field is a function of the triangle alone, whichever edge it
// is seen from (the optimizer caches edge costs on that).
inline void rotate_to_smallest(index_t& i0, index_t& i1, index_t& i2) {
  if (i1 < i0 && i1 < i2) {
    const index_t t = i0;
    i0 = i1, i1 = i2, i2 = t;
  } else if (i2 < i0 && i2 < i1) {
    const index_t t = i2;
    i2 = i1, i1 = i0, i0 = t;
  }
}

// Fast paths. Everything here decides exactly as the reference (flip_costs): the
// same predicates (exact) and, for the built-in costs, the same floating-
// point operations in the same order, only without the indirections.

// Orientation of three mesh vertices, exact: a plain determinant when the
// points satisfy core::lattice_exact (pixel centres do), else CGAL's.
inline bool plain_arithmetic_is_exact(const std::vector<Point2>& points) {
  return core::lattice_exact<2>(points, [](const Point2& p, int k) { return k == 0 ? p.x : p.y; });
}

struct Geometry {
  const Mesh2& mesh;
  bool plain_is_exact;  // plain_arithmetic_is_exact(mesh.points)

  int orient(index_t i, index_t j, index_t k) const {
    const Point2 &p = mesh.points[i], &q = mesh.points[j], &r = mesh.points[k];
    return core::orient<2>({core::Vec<2>{p.x, p.y}, {q.x, q.y}, {r.x, r.y}}, plain_is_exact);
  }
  // is_flippable (mesh.cpp) with the predicate above.
  bool flippable(index_t e) const {
    const index_t f = mesh.opp[e];
    if (f == no_edge) return false;
    const index_t a = mesh.tri[e], b = mesh.tri[f], c = mesh.tri[prev_edge(e)], d = mesh.tri[prev_edge(f)];
    return orient(d, c, a) > 0 && orient(c, d, b) > 0;
  }
};

// The acceptance rule of the procedure: the core's (core/local_cost.hpp).
inline bool accept(const FlipCosts& costs, double tolerance, double& gain) {
  gain = costs.gain();
  return costs.improves(tolerance);
}

// Any cost: flip_costs.
struct ReferenceEvaluator {
  const Mesh2& mesh;
  const std::vector<float>& values;
  int K;
  const CostFunction& cost;
  Geometry geometry;
  double tolerance;

  static constexpr bool caches_terms = false;
  struct Scratch {
    Scratch(index_t, index_t) {}
  };
  double fill(Scratch&, index_t, index_t) const { return 0; }
  bool decide(index_t e, double& gain, long long&, Scratch&) const {
    if (!geometry.flippable(e)) return false;
    return accept(flip_costs(mesh, values, K, cost, e), tolerance, gain);
  }
  void commit(index_t, index_t, const Scratch&) const {}
};

// The quadrilateral a, b, c, d of the flip diagram (mesh.hpp) around edge
// e, when e can flip and its four vertices do not hold the same value in
// every channel (a flat quadrilateral, counted in `flat`, never flips for
// the fast evaluators' costs).
template <int KT>
bool open_quad(const Geometry& geometry, const float* z, int K, index_t e, index_t q[4], long long& flat) {
  if (!geometry.flippable(e)) return false;
  const Mesh2& mesh = geometry.mesh;
  const index_t f = mesh.opp[e];
  q[0] = mesh.tri[e], q[1] = mesh.tri[f], q[2] = mesh.tri[prev_edge(e)], q[3] = mesh.tri[prev_edge(f)];
  const int n = KT > 0 ? KT : K;
  const float* za = z + static_cast<std::size_t>(q[0]) * n;
  for (int i = 1; i < 4; ++i) {
    const float* zi = z + static_cast<std::size_t>(q[i]) * n;
    for (int k = 0; k < n; ++k)
      if (za[k] != zi[k]) return true;
  }
  ++flat;
  return false;
}

// Doubles for half-edges [first, end), each page allocated (filled with
// `unknown`) when first reached, so that a region that reads few of its
// half-edges holds few pages.
class TermPages {
 public:
  static constexpr double unknown = -1;  // terms are >= 0
  TermPages(index_t first, index_t end)
      : first_(first), pages_(static_cast<std::size_t>((end - first + page_size - 1) / page_size)) {}
  double& at(index_t h) {
    const index_t i = h - first_;
    std::unique_ptr<double[]>& page = pages_[static_cast<std::size_t>(i / page_size)];
    if (!page) {
      page = std::make_unique_for_overwrite<double[]>(page_size);  // written once, by the fill
      std::fill_n(page.get(), page_size, unknown);
    }
    return page[static_cast<std::size_t>(i % page_size)];
  }

 private:
  static constexpr index_t page_size = 4096;
  index_t first_;
  std::vector<std::unique_ptr<double[]>> pages_;
};

// sederberg and sederberg-edge: triangle_field, edge_cost and
// sederberg_cost inlined for KT channels (0: K at run time), with the same
// operations in the same order, hence the same values.
//
// Edge costs are cached: a region's Scratch holds the term of the edge of
// each of its half-edges read so far (both twins; 0 on the hull), computed
// when first read. A term depends only on the two triangles (fields are
// computed from the smallest vertex, and the Sederberg cost is symmetric
// bit for bit), so the cached value is what flip_costs would compute, and
// a region's cache starts empty without changing a decision; a flip
// rewrites the five terms it changes. The cache lives while its region
// runs: the memory is that of the regions running at once, not a double a
// half-edge of the whole mesh. A test then needs the
// two new triangles' fields and the new terms, summed one by one: it stops
// as soon as the partial sum rules the flip out (the terms are >= 0, a
// rounded sum of them never decreases, and the acceptance rule only gets
// harder as `after` grows). On a flat quadrilateral the gradients of t0,
// t1 and of both new triangles are exactly 0, so all ten terms are exactly
// 0: the gain is 0 and the edge never flips.
template <int KT>
struct SederbergEvaluator {
  const Mesh2& mesh;
  const float* z;
  int K;
  bool weighted;  // facet_weighted_content (else facet_sum)
  Geometry geometry;
  double tolerance;

  static constexpr int capacity = KT > 0 ? KT : max_cost_channels;
  struct Field {
    bool present = false;
    double area = 0;
    double g[capacity][2];
    double norm2[capacity];  // g . g, summed as sederberg_cost does
  };
  // A region's cached terms, and the five new terms of the last accepted
  // test, in the order of `after`.
  struct Scratch {
    Scratch(index_t first_half_edge, index_t end_half_edge) : cache(first_half_edge, end_half_edge) {}
    TermPages cache;
    double terms[5];
  };
  int channels() const { return KT > 0 ? KT : K; }

  void field(index_t i0, index_t i1, index_t i2, Field& t) const {
    rotate_to_smallest(i0, i1, i2);
    const int n = channels();
    t.present = true;
    const Point2 &p0 = mesh.points[i0], &p1 = mesh.points[i1], &p2 = mesh.points[i2];
    const double ux = p1.x - p0.x, uy = p1.y - p0.y, vx = p2.x - p0.x, vy = p2.y - p0.y;
    const double det = ux * vy - uy * vx;
    t.area = 0.5 * std::abs(det);
    const double inv = 1.0 / det;
    const float *z0 = z + static_cast<std::size_t>(i0) * n, *z1 = z + static_cast<std::size_t>(i1) * n,
                *z2 = z + static_cast<std::size_t>(i2) * n;
    for (int k = 0; k < n; ++k) {
      const double d1 = double(z1[k]) - z0[k], d2 = double(z2[k]) - z0[k];
      t.g[k][0] = (d1 * vy - d2 * uy) * inv;
      t.g[k][1] = (d2 * ux - d1 * vx) * inv;
      t.norm2[k] = t.g[k][0] * t.g[k][0] + t.g[k][1] * t.g[k][1];
    }
  }
  void across(index_t h, Field& t) const {
    const index_t o = mesh.opp[h];
    if (o == no_edge) {
      t.present = false;
      return;
    }
    const index_t s = 3 * tri_of(o);
    field(mesh.tri[s], mesh.tri[s + 1], mesh.tri[s + 2], t);
  }
  double edge(const Field& s, const Field& t) const {
    if (!s.present || !t.present) return 0;
    double c = 0;
    for (int k = 0; k < channels(); ++k) {
      const double dot = s.g[k][0] * t.g[k][0] + s.g[k][1] * t.g[k][1];
      c += std::max(0.0, std::sqrt(s.norm2[k] * t.norm2[k]) - dot);
    }
    if (weighted) c *= (s.area + t.area) / 3.0;
    return c;
  }
  // The term of interior edge e, from scratch.
  double edge_term(index_t e) const {
    const index_t s = 3 * tri_of(e), t = 3 * tri_of(mesh.opp[e]);
    Field fs, ft;
    field(mesh.tri[s], mesh.tri[s + 1], mesh.tri[s + 2], fs);
    field(mesh.tri[t], mesh.tri[t + 1], mesh.tri[t + 2], ft);
    return edge(fs, ft);
  }
  static constexpr bool caches_terms = true;
  // Fills a region's cache with the terms of its half-edges [first, end)
  // (and of their twins in it), as the first phase starts; returns the sum
  // of the terms of the edges whose smaller half-edge is the region's, in
  // half-edge order, so that the regions' sums make the total.
  double fill(Scratch& scratch, index_t first, index_t end) const {
    TermPages& C = scratch.cache;
    double sum = 0;
    for (index_t h = first; h < end; ++h) {
      const index_t o = mesh.opp[h];
      if (o == no_edge) {
        C.at(h) = 0;
        continue;
      }
      const bool twin_inside = o >= first && o < end;
      if (twin_inside && o < h) continue;  // stored with its twin
      const double c = edge_term(h);
      C.at(h) = c;
      if (twin_inside) C.at(o) = c;
      if (h < o) sum += c;
    }
    return sum;
  }
  // The cached term of half-edge h, computed on its first read. Its twin's
  // triangle is the region's (the schedule defers tests that reach beyond).
  double cached_term(index_t h, TermPages& cache) const {
    double& slot = cache.at(h);
    if (slot < 0) {
      const index_t o = mesh.opp[h];
      slot = o == no_edge ? 0.0 : edge_term(h);
      if (o != no_edge) cache.at(o) = slot;
    }
    return slot;
  }
  bool decide(index_t e, double& gain, long long& flat, Scratch& scratch) const {
    index_t q[4];
    if (!open_quad<KT>(geometry, z, K, e, q, flat)) return false;
    const index_t f = mesh.opp[e], a = q[0], b = q[1], c = q[2], d = q[3];
    TermPages& C = scratch.cache;
    // edge(t0, t1) + edge(t0, n_bc) + edge(t0, n_ca) + edge(t1, n_ad) + edge(t1, n_db)
    double before = cached_term(e, C);
    for (index_t h : {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)}) before += cached_term(h, C);
    Field t0n, t1n, n[4];
    field(d, c, a, t0n);
    field(c, d, b, t1n);
    double* term = scratch.terms;
    // edge(t0n, t1n) + edge(t1n, n_bc) + edge(t0n, n_ca) + edge(t0n, n_ad) + edge(t1n, n_db)
    FlipCosts costs{before, term[0] = edge(t0n, t1n), 0.0};
    if (!accept(costs, tolerance, gain)) return false;
    const index_t outer[4] = {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)};  // bc, ca, ad, db
    const Field* inner[4] = {&t1n, &t0n, &t0n, &t1n};
    for (int i = 0; i < 4; ++i) {
      across(outer[i], n[i]);
      costs.after += term[i + 1] = edge(*inner[i], n[i]);
      if (!accept(costs, tolerance, gain)) return false;
    }
    // Accepted without the noise scale, which only makes the rule harder:
    // now the scale, summed as flip_costs does (before's terms, then after's).
    Field t0, t1;
    field(a, b, c, t0);
    field(b, a, d, t1);
    const Field* before_pairs[5][2] = {{&t0, &t1}, {&t0, &n[0]}, {&t0, &n[1]}, {&t1, &n[2]}, {&t1, &n[3]}};
    const Field* after_pairs[5][2] = {{&t0n, &t1n}, {&t1n, &n[0]}, {&t0n, &n[1]}, {&t0n, &n[2]}, {&t1n, &n[3]}};
    for (const auto& pair : before_pairs) add_noise(*pair[0], *pair[1], costs.noise_scale);
    for (const auto& pair : after_pairs) add_noise(*pair[0], *pair[1], costs.noise_scale);
    return accept(costs, tolerance, gain);
  }
  // edge_cost's noise scale of the term of s and t.
  void add_noise(const Field& s, const Field& t, double& noise) const {
    if (!s.present || !t.present) return;
    const double weight = weighted ? (s.area + t.area) / 3.0 : 1.0;
    for (int k = 0; k < channels(); ++k) noise += std::sqrt(s.norm2[k] * t.norm2[k]) * weight;
  }
  // After flip_edge(mesh, e): stores the new terms. The slots of the flip
  // diagram now hold e = d->c, next(e) = c->a, prev(e) = a->d,
  // next(f) = d->b, prev(f) = b->c.
  void commit(index_t e, index_t f, Scratch& scratch) const {
    TermPages& C = scratch.cache;
    const index_t slots[5] = {e, prev_edge(f), next_edge(e), prev_edge(e), next_edge(f)};  // cd, bc, ca, ad, db
    for (int i = 0; i < 5; ++i) {
      const index_t h = slots[i];
      C.at(h) = scratch.terms[i];
      if (mesh.opp[h] != no_edge) C.at(mesh.opp[h]) = scratch.terms[i];
    }
  }
};

// variance: simplex_cost with variance_weight inlined. On a flat
// quadrilateral all four variances are exactly 0 ((3v) / 3 == v), so the
// gain is 0.
template <int KT>
struct VarianceEvaluator {
  const Mesh2& mesh;
  const float* z;
  int K;
  Geometry geometry;
  double tolerance;

  double triangle(index_t i0, index_t i1, index_t i2) const {
    const int n = KT > 0 ? KT : K;
    const double area = 0.5 * std::abs(signed_area2(mesh.points[i0], mesh.points[i1], mesh.points[i2]));
    const float *z0 = z + static_cast<std::size_t>(i0) * n, *z1 = z + static_cast<std::size_t>(i1) * n,
                *z2 = z + static_cast<std::size_t>(i2) * n;
    double w = 0;
    for (int k = 0; k < n; ++k) {
      const double v[3] = {z0[k], z1[k], z2[k]};
      double mean = 0;
      for (int i = 0; i < 3; ++i) mean += v[i];
      mean /= 3;
      double var = 0;
      for (int i = 0; i < 3; ++i) var += (v[i] - mean) * (v[i] - mean);
      w += var / 3;
    }
    return area * w;
  }
  static constexpr bool caches_terms = false;
  struct Scratch {
    Scratch(index_t, index_t) {}
  };
  double fill(Scratch&, index_t, index_t) const { return 0; }
  void commit(index_t, index_t, const Scratch&) const {}
  bool decide(index_t e, double& gain, long long& flat, Scratch&) const {
    index_t q[4];
    if (!open_quad<KT>(geometry, z, K, e, q, flat)) return false;
    const index_t a = q[0], b = q[1], c = q[2], d = q[3];
    const double before = triangle(a, b, c) + triangle(b, a, d);
    const double after = triangle(d, c, a) + triangle(c, d, b);
    return accept(FlipCosts{before, after, 0.0}, tolerance, gain);  // simplex weights: no noise scale
  }
};

inline bool is_sederberg(const CostFunction& cost) {
  return cost.facet_cost == &sederberg_facet_cost && !cost.facet_geometry &&
         (cost.form == CostForm::facet_weighted_content || cost.form == CostForm::facet_sum);
}

}  // namespace ddt::flip_evaluators
