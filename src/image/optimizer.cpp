#include "image/optimizer.hpp"

#include "util/chunked_sum.hpp"
#include "core/local_cost.hpp"
#include "core/predicates.hpp"
#include "core/schedule.hpp"
#include "util/error.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>

namespace ddt {
namespace {

// Per-channel gradients of the linear interpolant on one triangle, and its area.
struct TriangleField {
  bool present = false;
  index_t ids[3] = {0, 0, 0};
  double area = 0;
  double grad[max_cost_channels][2];
};

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

TriangleField triangle_field(const Mesh2& mesh, const std::vector<float>& values, int K, index_t i0, index_t i1,
                             index_t i2) {
  rotate_to_smallest(i0, i1, i2);
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
// (area(s) + area(t)) / 3 in the weighted-content form; adds the term's
// noise scale (|g1| |g2| times that weight, per channel), as the core's
// facet_term does.
double edge_cost(const Mesh2& mesh, const std::vector<float>& values, const CostFunction& cost, int K,
                 const TriangleField& s, const TriangleField& t, index_t u, index_t v, double* noise = nullptr) {
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
  const double weight = cost.form == CostForm::facet_weighted_content ? (s.area + t.area) / 3.0 : 1.0;
  if (noise)
    for (int k = 0; k < K; ++k) {
      const double n1 = s.grad[k][0] * s.grad[k][0] + s.grad[k][1] * s.grad[k][1];
      const double n2 = t.grad[k][0] * t.grad[k][0] + t.grad[k][1] * t.grad[k][1];
      *noise += std::sqrt(n1 * n2) * weight;
    }
  return c * weight;
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


// ---------------------------------------------------------------------------
// Fast paths. Everything below decides exactly as the reference above: the
// same predicates (exact) and, for the built-in costs, the same floating-
// point operations in the same order, only without the indirections.

// Orientation of three mesh vertices, exact: a plain determinant when the
// points satisfy core::lattice_exact (pixel centres do), else CGAL's.
bool plain_arithmetic_is_exact(const std::vector<Point2>& points) {
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
      page = std::make_unique<double[]>(page_size);
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

bool is_sederberg(const CostFunction& cost) {
  return cost.facet_cost == &sederberg_facet_cost && !cost.facet_geometry &&
         (cost.form == CostForm::facet_weighted_content || cost.form == CostForm::facet_sum);
}

// ---------------------------------------------------------------------------
// The schedule: regions of consecutive triangle ids (see optimizer.hpp).

// Flag bits per half-edge: queued by the initial scan, or on a list.
constexpr std::uint8_t queued_initially = 1, queued = 2;

struct Region {
  index_t first = 0, last = 0;  // triangles [first, last)
  bool owns(index_t t) const { return t >= first && t < last; }
};

struct RegionResult {
  double initial_cost = 0;         // Evaluator::fill's sum (the first phase)
  int iterations = 0;
  long long flips = 0, tests = 0, flat = 0;
  double gains = 0;                // sum of the gains of its flips, in order
  std::vector<index_t> deferred;   // edges another region must test
};

// Shared state of one optimization run.
struct Run {
  Mesh2& mesh;
  std::vector<std::uint8_t> flags;  // per half-edge
  const LawsonOptions& options;
  bool reaches_neighbours;  // facet costs: a flip changes the neighbours' edges too
  std::atomic<long long> tests_reported{0};
  std::mutex report_mutex;

  Run(Mesh2& m, const LawsonOptions& o, bool reach)
      : mesh(m), flags(m.half_edge_count(), 0), options(o), reaches_neighbours(reach) {}

  void report_tests(long long add) {
    const long long total = tests_reported.fetch_add(add) + add;
    if (!options.on_tests) return;
    std::unique_lock<std::mutex> lock(report_mutex, std::try_to_lock);
    if (lock.owns_lock()) options.on_tests(total);
  }
};

// Lawson's loop inside one region. The first iteration scans the region's
// half-edges flagged queued_initially (the reference's initial active list,
// in the same order) when `scan` (the first phase: the evaluator's cache is
// filled then), else works through `active`. Edges whose
// test or whose queueing would touch a triangle outside the region go to
// result.deferred. on_iteration(iteration, flips, gains so far), if given.
template <class Evaluator, class OnIteration>
void run_region(Run& run, const Evaluator& evaluator, const Region& region, bool scan, std::vector<index_t> active,
                RegionResult& result, OnIteration on_iteration) {
  Mesh2& mesh = run.mesh;
  std::vector<std::uint8_t>& flags = run.flags;
  std::vector<index_t> candidate;
  typename Evaluator::Scratch scratch(3 * region.first, 3 * region.last);
  if (scan) result.initial_cost = evaluator.fill(scratch, 3 * region.first, 3 * region.last);
  long long unreported = 0;
  auto enqueue = [&](index_t h) {
    const index_t o = mesh.opp[h];
    if (o == no_edge) return;
    if (!region.owns(tri_of(h)) || !region.owns(tri_of(o))) {
      result.deferred.push_back(h);
      return;
    }
    if (flags[h] || flags[o]) return;
    flags[h] = queued;
    candidate.push_back(h);
  };
  // Tests e (flag already cleared); returns 1 when it flipped.
  auto test = [&](index_t e) -> long long {
    const index_t f = mesh.opp[e];
    if (f == no_edge) return 0;
    bool inside = region.owns(tri_of(f));
    for (index_t h : {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)}) {
      const index_t o = mesh.opp[h];
      if (o != no_edge && !region.owns(tri_of(o))) inside = false;
    }
    if (!inside) {
      result.deferred.push_back(e);
      return 0;
    }
    ++result.tests;
    if (++unreported == 4096) {
      run.report_tests(unreported);
      unreported = 0;
    }
    double gain = 0;
    if (!evaluator.decide(e, gain, result.flat, scratch)) return 0;
    flip_edge(mesh, e);
    evaluator.commit(e, f, scratch);
    result.gains += gain;
    for (index_t h : {e, next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)}) enqueue(h);
    if (run.reaches_neighbours) {
      // Facet costs reach one triangle further: the edges of the four
      // neighbours depend on the gradients of t0 and t1.
      for (index_t h : {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)}) {
        const index_t o = mesh.opp[h];
        if (o == no_edge) continue;
        enqueue(next_edge(o));
        enqueue(prev_edge(o));
      }
    }
    return 1;
  };

  if (scan) {
    bool any = false;
    for (index_t e = 3 * region.first; e < 3 * region.last && !any; ++e) any = flags[e] & queued_initially;
    if (!any) scan = false;
  }
  auto scan_initial = [&](long long& flips) {
    for (index_t e = 3 * region.first; e < 3 * region.last; ++e) {
      if (!(flags[e] & queued_initially)) continue;
      flags[e] = 0;
      flips += test(e);
    }
  };
  core::lawson_iterations(
      scan, std::move(active), candidate, run.options.max_iterations, result.iterations, result.flips,
      [] { return 0LL; }, scan_initial,
      [&](index_t e, long long& flips) {
        flags[e] = 0;
        flips += test(e);
      },
      [&](index_t e) { flags[e] = 0; },
      [&](int iteration, long long flips) { on_iteration(iteration, flips, result.gains); });
  if (scan && result.iterations == 0)  // the scan never ran (max_iterations <= 0)
    for (index_t e = 3 * region.first; e < 3 * region.last; ++e) flags[e] &= static_cast<std::uint8_t>(~queued_initially);
  run.report_tests(unreported);
}

// The regions of a partition: `size` triangles each, the first starting at
// `start` (in (-size, 0]) and clipped at 0.
std::vector<Region> partition(index_t triangles, long long size, long long start) {
  std::vector<Region> regions;
  for (long long lo = start; lo < triangles; lo += size) {
    Region r;
    r.first = static_cast<index_t>(std::max(0LL, lo));
    r.last = static_cast<index_t>(std::min<long long>(triangles, lo + size));
    if (r.first < r.last) regions.push_back(r);
  }
  return regions;
}

template <class Evaluator>
void optimize_with(Run& run, const Evaluator& evaluator, LawsonStats& stats) {
  Mesh2& mesh = run.mesh;
  const LawsonOptions& options = run.options;
  const index_t T = mesh.triangle_count();
  const bool forced = options.region_triangles > 0;
  const long long size = forced ? options.region_triangles
                         : options.region_triangles == 0 ? default_region_triangles
                                                         : 0;
  // The total before: total_cost's, or the sum of the first phase's fills.
  auto cost_before = [&](const std::vector<RegionResult>& results) {
    if (!Evaluator::caches_terms) return stats.cost_before;
    double sum = 0;
    for (const RegionResult& result : results) sum += result.initial_cost;
    return sum;
  };
  double cost_now = stats.cost_before;

  if (size <= 0 || (!forced && T <= 2 * size)) {  // one region: the reference procedure, iteration by iteration
    std::vector<RegionResult> results(1);
    RegionResult& result = results[0];
    run_region(run, evaluator, Region{0, T}, true, {}, result,
               [&](int iteration, long long flips, double gains) {
                 stats.cost_before = cost_before(results);
                 if (options.on_iteration) options.on_iteration(iteration, flips, stats.cost_before - gains);
               });
    stats.cost_before = cost_before(results);
    stats.cost_after = stats.cost_before - result.gains;
    stats.iterations = result.iterations;
    stats.flips = result.flips;
    stats.tests = result.tests;
    stats.skipped_flat = result.flat;
    return;
  }

  auto no_report = [](int, long long, double) {};
  std::vector<index_t> list;  // edges queued for the next phase, in a fixed order
  // Even phases: regions [k size, (k+1) size); odd phases: shifted by half
  // a region; `single`: one region for what is left (core/schedule.hpp).
  auto run_phase = [&](int phase, bool single) {
    const long long shift = phase % 2 == 1 ? size / 2 : 0;
    const long long boundary = ((options.region_origin + shift) % size + size) % size;  // first boundary >= 0
    const long long start = boundary == 0 ? 0 : boundary - size;
    const std::vector<Region> regions = single ? std::vector<Region>{Region{0, T}} : partition(T, size, start);
    if (phase == 0) stats.regions = static_cast<int>(regions.size());
    std::vector<RegionResult> results(regions.size());
    std::vector<std::vector<index_t>> buckets(regions.size());
    for (index_t h : list) buckets[single ? 0 : static_cast<std::size_t>((tri_of(h) - start) / size)].push_back(h);
    list.clear();
    tbb::parallel_for(std::size_t(0), regions.size(), [&](std::size_t r) {
      run_region(run, evaluator, regions[r], phase == 0, std::move(buckets[r]), results[r], no_report);
    });
    if (phase == 0) cost_now = stats.cost_before = cost_before(results);
    long long flips_now = 0;
    for (RegionResult& result : results) {
      flips_now += result.flips;
      stats.tests += result.tests;
      stats.skipped_flat += result.flat;
      cost_now -= result.gains;
      for (index_t h : result.deferred) {
        const index_t o = mesh.opp[h];
        if (o == no_edge || run.flags[h] || run.flags[o]) continue;
        run.flags[h] = queued;
        list.push_back(h);
      }
    }
    stats.flips += flips_now;
    stats.iterations = phase + 1;
    if (options.on_iteration) options.on_iteration(phase + 1, flips_now, cost_now);
    return flips_now;
  };
  core::run_region_phases(options.max_iterations, run_phase, [&] { return !list.empty(); });
  stats.cost_after = cost_now;
}

}  // namespace
double total_cost(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost) {
  if (cost.form == CostForm::simplex_weight)
    return chunked_sum(mesh.triangle_count(), [&](index_t t) {
      return triangle_cost(mesh, values, K, cost, mesh.tri[3 * t], mesh.tri[3 * t + 1], mesh.tri[3 * t + 2]);
    });
  if (is_sederberg(cost) && K >= 1 && K <= max_cost_channels) {
    const SederbergEvaluator<0> fast{mesh, values.data(), K, cost.form == CostForm::facet_weighted_content,
                                     Geometry{mesh, false}, 0.0};
    return chunked_sum(mesh.half_edge_count(), [&](index_t e) {
      return mesh.opp[e] == no_edge || mesh.opp[e] < e ? 0.0 : fast.edge_term(e);
    });
  }
  return chunked_sum(mesh.half_edge_count(), [&](index_t e) {
    if (mesh.opp[e] == no_edge || mesh.opp[e] < e) return 0.0;
    const index_t s = tri_of(e), t = tri_of(mesh.opp[e]);
    const TriangleField fs = triangle_field(mesh, values, K, mesh.tri[3 * s], mesh.tri[3 * s + 1], mesh.tri[3 * s + 2]);
    const TriangleField ft = triangle_field(mesh, values, K, mesh.tri[3 * t], mesh.tri[3 * t + 1], mesh.tri[3 * t + 2]);
    return edge_cost(mesh, values, cost, K, fs, ft, mesh.tri[e], mesh.tri[next_edge(e)]);
  });
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
    return edge_cost(mesh, values, cost, K, s, t, u, v, &out.noise_scale);
  };
  // One term at a time: the noise scale is summed in this order too (the
  // fast evaluator repeats it).
  out.before = edge(t0, t1, a, b);
  out.before += edge(t0, n_bc, b, c);
  out.before += edge(t0, n_ca, c, a);
  out.before += edge(t1, n_ad, a, d);
  out.before += edge(t1, n_db, d, b);
  out.after = edge(t0n, t1n, c, d);
  out.after += edge(t1n, n_bc, b, c);
  out.after += edge(t0n, n_ca, c, a);
  out.after += edge(t0n, n_ad, a, d);
  out.after += edge(t1n, n_db, d, b);
  return out;
}

long long image_region_triangles(int width) {
  const long long row = 2LL * std::max(1, width - 1);  // triangles per row of cells
  const long long rows = std::max(64LL, (default_region_triangles + row / 2) / row);
  return rows * row;
}

LawsonStats optimize_lawson(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                            const LawsonOptions& options) {
  if (K < 1 || K > max_cost_channels)
    throw Error("the cost takes 1 to " + std::to_string(max_cost_channels) + " channels, got " + std::to_string(K));
  LawsonStats stats;
  Run run(mesh, options, cost.form != CostForm::simplex_weight);
  // The reference's initial active list: every interior edge once.
  tbb::parallel_for(tbb::blocked_range<index_t>(0, mesh.half_edge_count()), [&](const tbb::blocked_range<index_t>& r) {
    for (index_t e = r.begin(); e < r.end(); ++e)
      if (mesh.opp[e] != no_edge && e < mesh.opp[e]) run.flags[e] = queued_initially;
  });
  const Geometry geometry{mesh, plain_arithmetic_is_exact(mesh.points)};
  const double tol = options.relative_tolerance;
  const float* z = values.data();
  const bool fast = options.fast_evaluation;
  const bool variance = cost.form == CostForm::simplex_weight && cost.simplex_weight == &variance_weight;
  const bool weighted = cost.form == CostForm::facet_weighted_content;

  if (fast && is_sederberg(cost)) {
    // The totals: summed by the first phase's regions as they fill their
    // caches, then tracked from the gains (optimize_with).
    auto go = [&](const auto& evaluator) {
      optimize_with(run, evaluator, stats);
      if (stats.iterations == 0)  // no phase ran (max_iterations <= 0): nothing filled
        stats.cost_before = stats.cost_after = chunked_sum(mesh.half_edge_count(), [&](index_t e) {
          return mesh.opp[e] == no_edge || mesh.opp[e] < e ? 0.0 : evaluator.edge_term(e);
        });
    };
    switch (K) {
      case 1: go(SederbergEvaluator<1>{mesh, z, K, weighted, geometry, tol}); break;
      case 3: go(SederbergEvaluator<3>{mesh, z, K, weighted, geometry, tol}); break;
      case 4: go(SederbergEvaluator<4>{mesh, z, K, weighted, geometry, tol}); break;
      default: go(SederbergEvaluator<0>{mesh, z, K, weighted, geometry, tol}); break;
    }
    return stats;
  }
  stats.cost_before = total_cost(mesh, values, K, cost);
  if (fast && variance) {
    switch (K) {
      case 1: optimize_with(run, VarianceEvaluator<1>{mesh, z, K, geometry, tol}, stats); break;
      case 3: optimize_with(run, VarianceEvaluator<3>{mesh, z, K, geometry, tol}, stats); break;
      default: optimize_with(run, VarianceEvaluator<0>{mesh, z, K, geometry, tol}, stats); break;
    }
  } else {
    optimize_with(run, ReferenceEvaluator{mesh, values, K, cost, geometry, tol}, stats);
  }
  stats.cost_after = total_cost(mesh, values, K, cost);
  return stats;
}

}  // namespace ddt
