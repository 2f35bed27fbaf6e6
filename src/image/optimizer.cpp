#include "image/optimizer.hpp"

#include "image/flip_evaluators.hpp"
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
#include <mutex>

namespace ddt {
namespace {

using namespace flip_evaluators;

// Per-channel gradients of the linear interpolant on one triangle, and its area.
struct TriangleField {
  bool present = false;
  index_t ids[3] = {0, 0, 0};
  double area = 0;
  double grad[max_cost_channels][2];
};


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
// The schedule: regions of consecutive triangle ids (see optimizer.hpp).

// Flag bits per half-edge: queued by the initial scan, or on a list.
constexpr std::uint8_t queued_initially = 1, queued = 2;

// The two flag bits of every half-edge, packed by triangle (its three
// half-edges' in one byte, a third of a byte a half-edge): a region writes
// the bytes of its own triangles only, so regions never share one.
class HalfEdgeFlags {
 public:
  explicit HalfEdgeFlags(index_t half_edges) : bytes_(static_cast<std::size_t>(half_edges / 3), 0) {}
  std::uint8_t operator[](index_t h) const { return (bytes_[static_cast<std::size_t>(h / 3)] >> shift(h)) & 3; }
  void set(index_t h, std::uint8_t bits) {
    std::uint8_t& byte = bytes_[static_cast<std::size_t>(h / 3)];
    byte = static_cast<std::uint8_t>((byte & ~(3 << shift(h))) | (bits << shift(h)));
  }

 private:
  static int shift(index_t h) { return 2 * (h % 3); }
  std::vector<std::uint8_t> bytes_;
};

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
  HalfEdgeFlags flags;
  const LawsonOptions& options;
  bool reaches_neighbours;  // facet costs: a flip changes the neighbours' edges too
  std::atomic<long long> tests_reported{0};
  std::mutex report_mutex;

  Run(Mesh2& m, const LawsonOptions& o, bool reach)
      : mesh(m), flags(m.half_edge_count()), options(o), reaches_neighbours(reach) {}

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
  HalfEdgeFlags& flags = run.flags;
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
    flags.set(h, queued);
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
      flags.set(e, 0);
      flips += test(e);
    }
  };
  core::lawson_iterations(
      scan, std::move(active), candidate, run.options.max_iterations, result.iterations, result.flips,
      [] { return 0LL; }, scan_initial,
      [&](index_t e, long long& flips) {
        flags.set(e, 0);
        flips += test(e);
      },
      [&](index_t e) { flags.set(e, 0); },
      [&](int iteration, long long flips) { on_iteration(iteration, flips, result.gains); });
  if (scan && result.iterations == 0)  // the scan never ran (max_iterations <= 0)
    for (index_t e = 3 * region.first; e < 3 * region.last; ++e)
      flags.set(e, static_cast<std::uint8_t>(flags[e] & ~queued_initially));
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
        run.flags.set(h, queued);
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
  // By triangles: a triangle's flags share a byte.
  tbb::parallel_for(tbb::blocked_range<index_t>(0, mesh.triangle_count()), [&](const tbb::blocked_range<index_t>& r) {
    for (index_t e = 3 * r.begin(); e < 3 * r.end(); ++e)
      if (mesh.opp[e] != no_edge && e < mesh.opp[e]) run.flags.set(e, queued_initially);
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
        stats.cost_before = stats.cost_after = total_cost(mesh, values, K, cost);
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
