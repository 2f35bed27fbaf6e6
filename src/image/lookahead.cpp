#include "image/lookahead.hpp"

#include <algorithm>

namespace ddt {
namespace {

// The slots a flip of e rewrites: both triangles' vertices and twins, and
// the twins' back links. Restoring them undoes the flip exactly, slots
// included (a second flip would restore the mesh with its two triangles
// swapped, moving edges to slots a sweep has already passed).
struct FlipUndo {
  index_t t0 = 0, t1 = 0;
  index_t tri[6], opp[6], outer[6], outer_back[6];
  int outer_count = 0;

  FlipUndo(const Mesh2& m, index_t e) : t0(3 * tri_of(e)), t1(3 * tri_of(m.opp[e])) {
    for (int i = 0; i < 3; ++i) {
      tri[i] = m.tri[t0 + i], opp[i] = m.opp[t0 + i];
      tri[3 + i] = m.tri[t1 + i], opp[3 + i] = m.opp[t1 + i];
    }
    for (int i = 0; i < 6; ++i)
      if (opp[i] != no_edge) outer[outer_count] = opp[i], outer_back[outer_count++] = m.opp[opp[i]];
  }
  void restore(Mesh2& m) const {
    for (int i = 0; i < outer_count; ++i) m.opp[outer[i]] = outer_back[i];
    for (int i = 0; i < 3; ++i) {
      m.tri[t0 + i] = tri[i], m.opp[t0 + i] = opp[i];
      m.tri[t1 + i] = tri[3 + i], m.opp[t1 + i] = opp[3 + i];
    }
  }
};

}  // namespace

LookaheadStats optimize_lookahead(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                                  const LawsonOptions& lawson, const LookaheadOptions& options) {
  LookaheadStats stats;
  stats.first_lawson = optimize_lawson(mesh, values, K, cost, lawson);
  stats.cost_before = stats.first_lawson.cost_before;
  stats.cost_after = stats.first_lawson.cost_after;
  stats.lawson_flips = stats.first_lawson.flips;

  while (stats.sweeps < options.max_sweeps) {
    ++stats.sweeps;
    long long kept = 0;
    for (index_t e = 0; e < mesh.half_edge_count(); ++e) {
      if (mesh.opp[e] == no_edge || mesh.opp[e] < e || !is_flippable(mesh, e)) continue;
      const FlipCosts first = flip_costs(mesh, values, K, cost, e);
      const index_t f = mesh.opp[e];
      const FlipUndo undo(mesh, e);
      flip_edge(mesh, e);
      // The outer edges of the quadrilateral, in the slots of the flip
      // diagram after the flip: c->a, a->d, d->b, b->c.
      index_t best = no_edge;
      double best_gain = 0;
      for (index_t h : {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)}) {
        if (!is_flippable(mesh, h)) continue;
        const FlipCosts second = flip_costs(mesh, values, K, cost, h);
        const double gain = first.gain() + second.gain();
        const double scale = std::max(first.before + second.before, first.noise_scale + second.noise_scale);
        if (gain > lawson.relative_tolerance * scale && gain > best_gain) {
          best = h;
          best_gain = gain;
        }
      }
      if (best == no_edge) {
        undo.restore(mesh);
        continue;
      }
      flip_edge(mesh, best);
      ++kept;
    }
    stats.pairs += kept;
    if (kept == 0) break;
    const LawsonStats again = optimize_lawson(mesh, values, K, cost, lawson);
    stats.lawson_flips += again.flips;
    stats.cost_after = again.cost_after;
  }
  return stats;
}

}  // namespace ddt
