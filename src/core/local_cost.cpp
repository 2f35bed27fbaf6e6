#include "core/local_cost.hpp"

#include "util/chunked_sum.hpp"
#include "core/field.hpp"

#include <algorithm>
#include <cmath>

namespace ddt::core {
namespace {

template <int D>
struct Context {
  const SimplexMesh<D>& mesh;
  const float* values;
  int K;
  const CostFunction& cost;
  bool facet() const { return cost.form != CostForm::simplex_weight; }
  double value(index_t v, int k) const { return values[static_cast<std::size_t>(v) * K + k]; }
  SimplexField<D> field(const CellVertices<D>& ids) const {
    return simplex_field<D>(mesh.points, values, K, ids, facet());
  }
};

// The simplex weight summed over the channels.
template <int D>
double channel_weight(const Context<D>& ctx, const CellVertices<D>& ids) {
  double w = 0;
  for (int k = 0; k < ctx.K; ++k) {
    std::array<double, D + 1> z;
    for (int i = 0; i <= D; ++i) z[i] = ctx.value(ids[i], k);
    w += ctx.cost.simplex_weight(z.data(), D + 1);
  }
  return w;
}

template <int D>
double simplex_cost(const Context<D>& ctx, const SimplexField<D>& s) {
  return s.content * channel_weight<D>(ctx, s.ids);
}

template <int D>
index_t apex_of(const SimplexField<D>& s, const FacetKey<D>& facet) {
  for (index_t id : s.ids)
    if (!std::binary_search(facet.begin(), facet.end(), id)) return id;
  return s.ids[0];
}

// The unit normal of the facet's hyperplane pointing towards q:
// (q - base) with its components along the facet's edges removed
// (Gram-Schmidt), normalized.
template <int D>
Vec<D> facet_normal(const std::vector<Vec<D>>& points, const FacetKey<D>& facet, const Vec<D>& q) {
  std::array<Vec<D>, D - 1> basis;
  const Vec<D>& base = points[facet[0]];
  auto reject = [&](Vec<D> v, int count) {
    for (int j = 0; j < count; ++j) {
      double dot = 0;
      for (int k = 0; k < D; ++k) dot += v[k] * basis[j][k];
      for (int k = 0; k < D; ++k) v[k] -= dot * basis[j][k];
    }
    return v;
  };
  auto normalized = [](Vec<D> v) {
    double len = 0;
    for (double c : v) len += c * c;
    len = std::sqrt(len);
    for (double& c : v) c /= len;
    return v;
  };
  for (int j = 0; j < D - 1; ++j) {
    Vec<D> e;
    for (int k = 0; k < D; ++k) e[k] = points[facet[j + 1]][k] - base[k];
    basis[j] = normalized(reject(e, j));
  }
  Vec<D> v;
  for (int k = 0; k < D; ++k) v[k] = q[k] - base[k];
  return normalized(reject(v, D - 1));
}

// c(f) for the facet shared by s and t, times (content(s) + content(t)) /
// (D + 1) in the weighted-content form; adds the term's noise scale.
template <int D>
double facet_term(const Context<D>& ctx, const SimplexField<D>& s, const SimplexField<D>& t,
                  const FacetKey<D>& facet_ids, double* noise = nullptr) {
  FacetPair facet;
  facet.dim = D;
  Vec<D> normal;
  index_t a1 = 0, a2 = 0;
  if (ctx.cost.facet_geometry) {
    a1 = apex_of<D>(s, facet_ids), a2 = apex_of<D>(t, facet_ids);
    normal = facet_normal<D>(ctx.mesh.points, facet_ids, ctx.mesh.points[a2]);
    facet.normal = normal.data();
    facet.base = ctx.mesh.points[facet_ids[0]].data();
    facet.apex1 = ctx.mesh.points[a1].data();
    facet.apex2 = ctx.mesh.points[a2].data();
  }
  double c = 0;
  for (int k = 0; k < ctx.K; ++k) {
    facet.g1 = s.grad[k];
    facet.g2 = t.grad[k];
    if (ctx.cost.facet_geometry) {
      facet.z_base = ctx.value(facet_ids[0], k);
      facet.z_apex1 = ctx.value(a1, k);
      facet.z_apex2 = ctx.value(a2, k);
    }
    c += ctx.cost.facet_cost(facet);
  }
  const double weight =
      ctx.cost.form == CostForm::facet_weighted_content ? (s.content + t.content) / (D + 1) : 1.0;
  if (noise)
    for (int k = 0; k < ctx.K; ++k) {
      double n1 = 0, n2 = 0;
      for (int d = 0; d < D; ++d) n1 += s.grad[k][d] * s.grad[k][d], n2 += t.grad[k][d] * t.grad[k][d];
      *noise += std::sqrt(n1 * n2) * weight;
    }
  return c * weight;
}

// The key of facet i of a cell given by its vertices.
template <int D>
FacetKey<D> key_of(const CellVertices<D>& v, int i) {
  FacetKey<D> key;
  for (int j = 0, n = 0; j <= D; ++j)
    if (j != i) key[n++] = v[j];
  std::sort(key.begin(), key.end());
  return key;
}

}  // namespace

template <int D>
double total_cost(const SimplexMesh<D>& mesh, const float* values, int K, const CostFunction& cost) {
  const Context<D> ctx{mesh, values, K, cost};
  return chunked_sum(mesh.slot_count(), [&](index_t c) {
    if (!mesh.is_live(c)) return 0.0;
    const SimplexField<D> field = ctx.field(mesh.cell_vertices(c));
    if (!ctx.facet()) return simplex_cost<D>(ctx, field);
    double sum = 0;
    for (int i = 0; i <= D; ++i) {
      const index_t g = mesh.opp[(D + 1) * c + i];
      if (g == no_facet || cell_of<D>(g) < c) continue;
      sum += facet_term<D>(ctx, field, ctx.field(mesh.cell_vertices(cell_of<D>(g))), facet_key(mesh, (D + 1) * c + i));
    }
    return sum;
  });
}

template <int D>
LocalCosts flip_costs(const SimplexMesh<D>& mesh, const float* values, int K, const CostFunction& cost,
                      const FlipPlan<D>& plan) {
  constexpr int cap = max_flip_cells<D>;
  const Context<D> ctx{mesh, values, K, cost};
  LocalCosts out;
  std::array<SimplexField<D>, cap> old_f, new_f;
  for (int k = 0; k < plan.removed_count; ++k) old_f[k] = ctx.field(mesh.cell_vertices(plan.removed[k]));
  for (int k = 0; k < plan.inserted_count; ++k) new_f[k] = ctx.field(plan.inserted[k]);
  if (!ctx.facet()) {
    for (int k = 0; k < plan.removed_count; ++k) out.before += simplex_cost<D>(ctx, old_f[k]);
    for (int k = 0; k < plan.inserted_count; ++k) out.after += simplex_cost<D>(ctx, new_f[k]);
    return out;
  }
  // Facets on the region's boundary with an outside neighbour.
  struct Outer {
    FacetKey<D> key;
    SimplexField<D> field;
  };
  std::array<Outer, cap*(D + 1)> outer;
  int outer_count = 0;
  auto old_index = [&](index_t slot) {
    for (int k = 0; k < plan.removed_count; ++k)
      if (plan.removed[k] == slot) return k;
    return -1;
  };
  for (int k = 0; k < plan.removed_count; ++k) {
    const index_t c = plan.removed[k];
    for (int i = 0; i <= D; ++i) {
      const index_t g = mesh.opp[(D + 1) * c + i];
      if (g == no_facet) continue;
      const FacetKey<D> key = key_of<D>(old_f[k].ids, i);
      const int j = old_index(cell_of<D>(g));
      if (j >= 0) {
        if (j > k) out.before += facet_term<D>(ctx, old_f[k], old_f[j], key, &out.noise_scale);
        continue;
      }
      Outer& o = outer[outer_count++];
      o.key = key;
      o.field = ctx.field(mesh.cell_vertices(cell_of<D>(g)));
      out.before += facet_term<D>(ctx, old_f[k], o.field, key, &out.noise_scale);
    }
  }
  std::array<FacetKey<D>, cap*(D + 1)> keys;
  const int n_keys = (D + 1) * plan.inserted_count;
  for (int n = 0; n < n_keys; ++n) keys[n] = key_of<D>(plan.inserted[n / (D + 1)], n % (D + 1));
  for (int me = 0; me < n_keys; ++me) {
    const int k = me / (D + 1);
    bool inner = false;
    for (int other = 0; other < n_keys && !inner; ++other)
      if (other / (D + 1) != k && same_ids(keys[other], keys[me])) {
        inner = true;
        if (other / (D + 1) > k) out.after += facet_term<D>(ctx, new_f[k], new_f[other / (D + 1)], keys[me], &out.noise_scale);
      }
    if (inner) continue;
    for (int o = 0; o < outer_count; ++o)
      if (same_ids(outer[o].key, keys[me])) {
        out.after += facet_term<D>(ctx, new_f[k], outer[o].field, keys[me], &out.noise_scale);
        break;
      }
  }
  return out;
}

template <int D>
double cell_cost(const SimplexMesh<D>& mesh, const float* values, int K, const CostFunction& cost,
                 const CellVertices<D>& ids) {
  const Context<D> ctx{mesh, values, K, cost};
  return simplex_cost<D>(ctx, ctx.field(ids));
}

template <int D>
LocalCosts flip_costs(const SimplexMesh<D>& mesh, const float* values, int K, const CostFunction& cost,
                      const FlipPlan<D>& plan, const double* removed_costs, double* inserted_costs) {
  LocalCosts out;
  for (int k = 0; k < plan.removed_count; ++k) out.before += removed_costs[k];
  const Context<D> ctx{mesh, values, K, cost};
  for (int k = 0; k < plan.inserted_count; ++k) {
    inserted_costs[k] = plan.contents_known ? plan.inserted_content[k] * channel_weight<D>(ctx, plan.inserted[k])
                                            : cell_cost<D>(mesh, values, K, cost, plan.inserted[k]);
    out.after += inserted_costs[k];
  }
  return out;
}

#define DDT_CORE_INSTANTIATE(D)                                                                                 \
  template double total_cost<D>(const SimplexMesh<D>&, const float*, int, const CostFunction&);                 \
  template LocalCosts flip_costs<D>(const SimplexMesh<D>&, const float*, int, const CostFunction&, \
                                    const FlipPlan<D>&);                                                        \
  template LocalCosts flip_costs<D>(const SimplexMesh<D>&, const float*, int, const CostFunction&, \
                                    const FlipPlan<D>&, const double*, double*);                                \
  template double cell_cost<D>(const SimplexMesh<D>&, const float*, int, const CostFunction&, const CellVertices<D>&);
DDT_CORE_INSTANTIATE(2)
DDT_CORE_INSTANTIATE(3)
DDT_CORE_INSTANTIATE(4)
#undef DDT_CORE_INSTANTIATE

}  // namespace ddt::core
