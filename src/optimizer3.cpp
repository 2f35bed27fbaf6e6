#include "optimizer3.hpp"

#include "error.hpp"
#include "lawson.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace ddt {
namespace {

// Per-channel gradients of the linear interpolant on one tetrahedron, and
// its volume.
struct TetField {
  index_t ids[4] = {0, 0, 0, 0};
  double volume = 0;
  double grad[max_cost_channels][3];
};

struct Context {
  const Mesh3& mesh;
  const std::vector<float>& values;
  int K;
  const CostFunction& cost;
  bool facet() const { return cost.form != CostForm::simplex_weight; }
};

double value(const Context& ctx, index_t v, int k) { return ctx.values[static_cast<std::size_t>(v) * ctx.K + k]; }

TetField tet_field(const Context& ctx, const index_t* ids) {
  TetField t;
  for (int i = 0; i < 4; ++i) t.ids[i] = ids[i];
  const Point3 &p0 = ctx.mesh.points[ids[0]], &p1 = ctx.mesh.points[ids[1]], &p2 = ctx.mesh.points[ids[2]],
               &p3 = ctx.mesh.points[ids[3]];
  const double e1[3] = {p1.x - p0.x, p1.y - p0.y, p1.z - p0.z};
  const double e2[3] = {p2.x - p0.x, p2.y - p0.y, p2.z - p0.z};
  const double e3[3] = {p3.x - p0.x, p3.y - p0.y, p3.z - p0.z};
  const double c23[3] = {e2[1] * e3[2] - e2[2] * e3[1], e2[2] * e3[0] - e2[0] * e3[2], e2[0] * e3[1] - e2[1] * e3[0]};
  const double det = e1[0] * c23[0] + e1[1] * c23[1] + e1[2] * c23[2];
  t.volume = std::abs(det) / 6.0;
  if (!ctx.facet()) return t;
  const double c31[3] = {e3[1] * e1[2] - e3[2] * e1[1], e3[2] * e1[0] - e3[0] * e1[2], e3[0] * e1[1] - e3[1] * e1[0]};
  const double c12[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  const double inv = 1.0 / det;
  for (int k = 0; k < ctx.K; ++k) {
    const double z0 = value(ctx, ids[0], k);
    const double d1 = value(ctx, ids[1], k) - z0, d2 = value(ctx, ids[2], k) - z0, d3 = value(ctx, ids[3], k) - z0;
    for (int c = 0; c < 3; ++c) t.grad[k][c] = (d1 * c23[c] + d2 * c31[c] + d3 * c12[c]) * inv;
  }
  return t;
}

double simplex_cost(const Context& ctx, const TetField& t) {
  double w = 0;
  for (int k = 0; k < ctx.K; ++k) {
    const double z[4] = {value(ctx, t.ids[0], k), value(ctx, t.ids[1], k), value(ctx, t.ids[2], k),
                         value(ctx, t.ids[3], k)};
    w += ctx.cost.simplex_weight(z, 4);
  }
  return t.volume * w;
}

index_t apex_of(const TetField& t, const index_t face[3]) {
  for (index_t id : t.ids)
    if (id != face[0] && id != face[1] && id != face[2]) return id;
  return t.ids[0];
}

// c(f) for the face shared by s and t, times (volume(s) + volume(t)) / 4 in
// the weighted-content form.
double face_cost(const Context& ctx, const TetField& s, const TetField& t, const index_t face[3],
                 double* noise = nullptr) {
  FacetPair facet;
  facet.dim = 3;
  double normal[3], base[3], apex1[3], apex2[3];
  index_t a1 = 0, a2 = 0;
  if (ctx.cost.facet_geometry) {
    a1 = apex_of(s, face), a2 = apex_of(t, face);
    const auto& P = ctx.mesh.points;
    const Point3 &u = P[face[0]], &v = P[face[1]], &w = P[face[2]];
    const double e1[3] = {v.x - u.x, v.y - u.y, v.z - u.z}, e2[3] = {w.x - u.x, w.y - u.y, w.z - u.z};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const Point3 &q1 = P[a1], &q2 = P[a2];
    const double side = (q2.x - u.x) * n[0] + (q2.y - u.y) * n[1] + (q2.z - u.z) * n[2];
    for (int c = 0; c < 3; ++c) normal[c] = (side < 0 ? -n[c] : n[c]) / len;
    base[0] = u.x, base[1] = u.y, base[2] = u.z;
    apex1[0] = q1.x, apex1[1] = q1.y, apex1[2] = q1.z;
    apex2[0] = q2.x, apex2[1] = q2.y, apex2[2] = q2.z;
    facet.normal = normal;
    facet.base = base;
    facet.apex1 = apex1;
    facet.apex2 = apex2;
  }
  double c = 0;
  for (int k = 0; k < ctx.K; ++k) {
    facet.g1 = s.grad[k];
    facet.g2 = t.grad[k];
    if (ctx.cost.facet_geometry) {
      facet.z_base = value(ctx, face[0], k);
      facet.z_apex1 = value(ctx, a1, k);
      facet.z_apex2 = value(ctx, a2, k);
    }
    c += ctx.cost.facet_cost(facet);
  }
  const double weight = ctx.cost.form == CostForm::facet_weighted_content ? (s.volume + t.volume) / 4.0 : 1.0;
  if (noise)
    for (int k = 0; k < ctx.K; ++k) {
      double n1 = 0, n2 = 0;
      for (int d = 0; d < 3; ++d) n1 += s.grad[k][d] * s.grad[k][d], n2 += t.grad[k][d] * t.grad[k][d];
      *noise += std::sqrt(n1 * n2) * weight;
    }
  return c * weight;
}

void face_ids(const index_t* tet, int i, index_t out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = tet[face_vertex[i][k]];
}

bool same_face(const index_t a[3], const index_t b[3]) {
  int match = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) match += a[i] == b[j];
  return match == 3;
}

LocalCosts local_costs(const Context& ctx, const FlipPlan& plan) {
  const Mesh3& mesh = ctx.mesh;
  LocalCosts out;
  TetField old_f[4], new_f[4];
  for (int k = 0; k < plan.old_count; ++k) old_f[k] = tet_field(ctx, &mesh.tet[4 * plan.old_tets[k]]);
  for (int k = 0; k < plan.new_count; ++k) new_f[k] = tet_field(ctx, plan.new_tets[k].data());
  if (!ctx.facet()) {
    for (int k = 0; k < plan.old_count; ++k) out.before += simplex_cost(ctx, old_f[k]);
    for (int k = 0; k < plan.new_count; ++k) out.after += simplex_cost(ctx, new_f[k]);
    return out;
  }
  // Faces on the region's boundary with an outside neighbour.
  struct Outer {
    index_t face[3];
    TetField field;
  };
  Outer outer[16];
  int n_outer = 0;
  auto old_index = [&](index_t slot) {
    for (int k = 0; k < plan.old_count; ++k)
      if (plan.old_tets[k] == slot) return k;
    return -1;
  };
  for (int k = 0; k < plan.old_count; ++k) {
    const index_t t = plan.old_tets[k];
    for (int i = 0; i < 4; ++i) {
      const index_t g = mesh.opp[4 * t + i];
      if (g == no_face) continue;
      index_t face[3];
      face_ids(&mesh.tet[4 * t], i, face);
      const int j = old_index(tet_of(g));
      if (j >= 0) {
        if (j > k) out.before += face_cost(ctx, old_f[k], old_f[j], face, &out.noise_scale);
        continue;
      }
      Outer& o = outer[n_outer++];
      for (int c = 0; c < 3; ++c) o.face[c] = face[c];
      o.field = tet_field(ctx, &mesh.tet[4 * tet_of(g)]);
      out.before += face_cost(ctx, old_f[k], o.field, face, &out.noise_scale);
    }
  }
  for (int k = 0; k < plan.new_count; ++k)
    for (int i = 0; i < 4; ++i) {
      index_t face[3];
      face_ids(plan.new_tets[k].data(), i, face);
      bool inner = false;
      for (int j = 0; j < plan.new_count && !inner; ++j) {
        if (j == k) continue;
        for (int i2 = 0; i2 < 4; ++i2) {
          index_t other[3];
          face_ids(plan.new_tets[j].data(), i2, other);
          if (same_face(face, other)) {
            inner = true;
            if (j > k) out.after += face_cost(ctx, new_f[k], new_f[j], face, &out.noise_scale);
            break;
          }
        }
      }
      if (inner) continue;
      for (int o = 0; o < n_outer; ++o)
        if (same_face(face, outer[o].face)) {
          out.after += face_cost(ctx, new_f[k], outer[o].field, face, &out.noise_scale);
          break;
        }
    }
  return out;
}

// The optimizer as a lawson.hpp Problem.
class Problem3 {
 public:
  Problem3(Mesh3& mesh, const std::vector<float>& values, int K, const CostFunction& cost)
      : mesh_(mesh), ctx_{mesh, values, K, cost} {}

  index_t item_slots() const { return 10 * mesh_.slot_count(); }

  template <class Add>
  void initial_items(Add add) const {
    // Interior faces once (from the smaller slot); edges once (from the
    // smallest slot around them) and only those with a ring that can flip.
    const index_t n = mesh_.slot_count();
    std::vector<std::uint16_t> mask(n, 0);
    tbb::parallel_for(index_t(0), n, [&](index_t t) {
      if (!mesh_.is_live(t)) return;
      std::uint16_t m = 0;
      for (int i = 0; i < 4; ++i) {
        const index_t g = mesh_.opp[4 * t + i];
        if (g != no_face && tet_of(g) > t) m |= 1u << i;
      }
      for (int k = 0; k < 6; ++k) {
        EdgeRing ring;
        const index_t a = mesh_.tet[4 * t + edge_vertex[k][0]], b = mesh_.tet[4 * t + edge_vertex[k][1]];
        if (!edge_ring(mesh_, t, a, b, ring, 4)) continue;
        if (ring.closed ? ring.size < 3 : ring.size != 2) continue;
        if (*std::min_element(ring.tets.begin(), ring.tets.begin() + ring.size) == t) m |= 1u << (4 + k);
      }
      mask[t] = m;
    });
    for (index_t t = 0; t < n; ++t)
      for (int i = 0; i < 10; ++i)
        if (mask[t] & (1u << i)) add(10 * t + i);
  }

  template <class Touch>
  double improve(index_t item, double relative_tolerance, Touch touch) {
    const index_t t = item / 10;
    const int k = item % 10;
    if (!mesh_.is_live(t)) return 0;
    // Price the proposals first; exact predicates only for a flip we would take.
    FlipPlan plans[2];
    int n = 0;
    if (k < 4) {
      n = propose_flip23(mesh_, 4 * t + k, plans[0]) ? 1 : 0;
    } else {
      const index_t a = mesh_.tet[4 * t + edge_vertex[k - 4][0]], b = mesh_.tet[4 * t + edge_vertex[k - 4][1]];
      n = propose_edge_flips(mesh_, t, a, b, plans);
    }
    // A simplex weight depends only on the vertex values: over a region
    // where they are all equal every tetrahedron has the same weight and
    // the volume is unchanged, so no flip there can gain.
    if (n > 0 && !ctx_.facet() && uniform_values(plans[0])) return 0;
    double gains[2] = {0, 0};
    for (int p = 0; p < n; ++p) {
      const LocalCosts lc = local_costs(ctx_, plans[p]);
      gains[p] = lc.improves(relative_tolerance) ? lc.gain() : 0;  // NaN (degenerate proposal) -> 0
    }
    // The better improving proposal that is valid.
    const int order[2] = {n == 2 && gains[1] > gains[0] ? 1 : 0, n == 2 && gains[1] > gains[0] ? 0 : 1};
    int best = -1;
    for (int j = 0; j < n && best < 0; ++j)
      if (gains[order[j]] > 0 && is_valid_flip(mesh_, plans[order[j]])) best = order[j];
    if (best < 0) return 0;
    const double best_gain = gains[best];
    const FlipPlan& plan = plans[best];
    index_t slots[4];
    apply_flip(mesh_, plan, slots);
    ++flips_.by_kind[static_cast<int>(plan.kind)];
    touch_around(slots, plan.new_count, touch);
    return best_gain;
  }

  double total_cost() const { return ddt::total_cost(mesh_, ctx_.values, ctx_.K, ctx_.cost); }
  const FlipCounts& flips() const { return flips_; }

 private:
  bool uniform_values(const FlipPlan& plan) const {
    const index_t first = mesh_.tet[4 * plan.old_tets[0]];
    for (int k = 0; k < plan.old_count; ++k)
      for (int i = 0; i < 4; ++i) {
        const index_t v = mesh_.tet[4 * plan.old_tets[k] + i];
        for (int c = 0; c < ctx_.K; ++c)
          if (value(ctx_, v, c) != value(ctx_, first, c)) return false;
      }
    return true;
  }

  // Faces and edges of the new tetrahedra, and for facet costs those of
  // their neighbours; each edge once per flip.
  template <class Touch>
  void touch_around(const index_t* slots, int count, Touch touch) {
    index_t tets[4 + 16];
    int n_tets = 0;
    for (int k = 0; k < count; ++k) tets[n_tets++] = slots[k];
    if (ctx_.facet())
      for (int k = 0; k < count; ++k)
        for (int i = 0; i < 4; ++i) {
          const index_t g = mesh_.opp[4 * slots[k] + i];
          if (g == no_face) continue;
          const index_t u = tet_of(g);
          if (std::find(tets, tets + n_tets, u) == tets + n_tets) tets[n_tets++] = u;
        }
    std::pair<index_t, index_t> seen[6 * 20];
    int n_seen = 0;
    for (int j = 0; j < n_tets; ++j) {
      const index_t t = tets[j];
      for (int i = 0; i < 4; ++i) {
        const index_t g = mesh_.opp[4 * t + i];
        if (g == no_face) continue;
        touch(tet_of(g) < t ? 10 * tet_of(g) + local_of(g) : 10 * t + i);
      }
      for (int k = 0; k < 6; ++k) {
        index_t a = mesh_.tet[4 * t + edge_vertex[k][0]], b = mesh_.tet[4 * t + edge_vertex[k][1]];
        if (a > b) std::swap(a, b);
        if (std::find(seen, seen + n_seen, std::make_pair(a, b)) != seen + n_seen) continue;
        seen[n_seen++] = {a, b};
        touch(10 * t + 4 + k);
      }
    }
  }

  Mesh3& mesh_;
  Context ctx_;
  FlipCounts flips_;
};

}  // namespace

bool LocalCosts::improves(double relative_tolerance) const {
  const double g = gain();
  return g > 0 && g > relative_tolerance * std::max({before, after, noise_scale});
}

long long FlipCounts::total() const {
  long long sum = 0;
  for (long long n : by_kind) sum += n;
  return sum;
}

std::string FlipCounts::summary() const {
  std::string s;
  for (int k = 0; k < flip_kind_count; ++k) {
    if (k) s += ", ";
    s += std::string(flip_kind_name(static_cast<FlipKind>(k))) + ": " + std::to_string(by_kind[k]);
  }
  return s;
}

double total_cost(const Mesh3& mesh, const std::vector<float>& values, int K, const CostFunction& cost) {
  const Context ctx{mesh, values, K, cost};
  double sum = 0;
  for (index_t t = 0; t < mesh.slot_count(); ++t) {
    if (!mesh.is_live(t)) continue;
    const TetField ft = tet_field(ctx, &mesh.tet[4 * t]);
    if (!ctx.facet()) {
      sum += simplex_cost(ctx, ft);
      continue;
    }
    for (int i = 0; i < 4; ++i) {
      const index_t g = mesh.opp[4 * t + i];
      if (g == no_face || tet_of(g) < t) continue;
      index_t face[3];
      face_ids(&mesh.tet[4 * t], i, face);
      sum += face_cost(ctx, ft, tet_field(ctx, &mesh.tet[4 * tet_of(g)]), face);
    }
  }
  return sum;
}

LocalCosts flip_costs(const Mesh3& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                      const FlipPlan& plan) {
  return local_costs(Context{mesh, values, K, cost}, plan);
}

Lawson3Stats optimize_lawson(Mesh3& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                             const Lawson3Options& options) {
  if (K < 1 || K > max_cost_channels)
    throw Error("the cost takes 1 to " + std::to_string(max_cost_channels) + " channels, got " + std::to_string(K));
  if (values.size() != mesh.points.size() * static_cast<std::size_t>(K))
    throw Error("optimize_lawson: " + std::to_string(values.size()) + " values for " +
                std::to_string(mesh.points.size()) + " vertices and " + std::to_string(K) + " channels");
  Problem3 problem(mesh, values, K, cost);
  FlipCounts previous;
  const LawsonRun run = run_lawson(problem, options.relative_tolerance, options.max_iterations,
                                   [&](int iteration, long long, double total) {
                                     if (!options.on_iteration) return;
                                     FlipCounts now;
                                     for (int k = 0; k < flip_kind_count; ++k)
                                       now.by_kind[k] = problem.flips().by_kind[k] - previous.by_kind[k];
                                     previous = problem.flips();
                                     options.on_iteration(iteration, now, total);
                                   });
  Lawson3Stats stats;
  stats.iterations = run.iterations;
  stats.flips = problem.flips();
  stats.tests = run.tests;
  stats.cost_before = run.cost_before;
  stats.cost_after = run.cost_after;
  return stats;
}

}  // namespace ddt
