#include "image/mesh.hpp"

#include "core/predicates.hpp"

#include <sstream>

namespace ddt {

int orientation(const Point2& p, const Point2& q, const Point2& r) {
  return core::orient<2>({core::Vec<2>{p.x, p.y}, {q.x, q.y}, {r.x, r.y}});
}

bool is_flippable(const Mesh2& mesh, index_t e) {
  const index_t f = mesh.opp[e];
  if (f == no_edge) return false;
  const Point2& a = mesh.points[mesh.tri[e]];
  const Point2& b = mesh.points[mesh.tri[f]];
  const Point2& c = mesh.points[mesh.tri[prev_edge(e)]];
  const Point2& d = mesh.points[mesh.tri[prev_edge(f)]];
  return orientation(d, c, a) > 0 && orientation(c, d, b) > 0;
}

void flip_edge(Mesh2& mesh, index_t e) {
  const index_t f = mesh.opp[e];
  const index_t e_bc = next_edge(e), e_ca = prev_edge(e);
  const index_t f_ad = next_edge(f), f_db = prev_edge(f);
  const index_t a = mesh.tri[e], b = mesh.tri[f];
  const index_t c = mesh.tri[e_ca], d = mesh.tri[f_db];
  const index_t bc = mesh.opp[e_bc], ca = mesh.opp[e_ca];
  const index_t ad = mesh.opp[f_ad], db = mesh.opp[f_db];

  // t0 = (d, c, a), t1 = (c, d, b): see the diagram in mesh.hpp.
  mesh.tri[e] = d;
  mesh.tri[e_bc] = c;
  mesh.tri[e_ca] = a;
  mesh.tri[f] = c;
  mesh.tri[f_ad] = d;
  mesh.tri[f_db] = b;

  mesh.link(e, f);
  mesh.link(e_bc, ca);  // slot next(e) now holds c->a
  mesh.link(e_ca, ad);  // slot prev(e) now holds a->d
  mesh.link(f_ad, db);  // slot next(f) now holds d->b
  mesh.link(f_db, bc);  // slot prev(f) now holds b->c
}

std::string check_mesh(const Mesh2& mesh) {
  std::ostringstream problem;
  const index_t n_half = mesh.half_edge_count();
  if (mesh.tri.size() % 3 != 0 || mesh.opp.size() != mesh.tri.size()) return "array sizes disagree";
  std::vector<char> used(mesh.points.size(), 0);
  index_t hull_edges = 0;
  for (index_t e = 0; e < n_half; ++e) {
    const index_t v = mesh.tri[e];
    if (v < 0 || v >= static_cast<index_t>(mesh.points.size())) {
      problem << "half-edge " << e << " has vertex " << v << " out of range";
      return problem.str();
    }
    used[v] = 1;
    const index_t t = mesh.opp[e];
    if (t == no_edge) {
      ++hull_edges;
      continue;
    }
    if (t < 0 || t >= n_half || mesh.opp[t] != e) {
      problem << "twin of half-edge " << e << " is not symmetric";
      return problem.str();
    }
    if (mesh.tri[t] != mesh.tri[next_edge(e)] || mesh.tri[next_edge(t)] != mesh.tri[e]) {
      problem << "half-edge " << e << " and its twin " << t << " join different vertices";
      return problem.str();
    }
  }
  for (index_t t = 0; t < mesh.triangle_count(); ++t) {
    const Point2& p = mesh.points[mesh.tri[3 * t]];
    const Point2& q = mesh.points[mesh.tri[3 * t + 1]];
    const Point2& r = mesh.points[mesh.tri[3 * t + 2]];
    if (orientation(p, q, r) <= 0) {
      problem << "triangle " << t << " is not strictly counter-clockwise";
      return problem.str();
    }
  }
  // On a triangulation of all points, hull vertices == hull edges.
  index_t unused = 0;
  for (char u : used) unused += u ? 0 : 1;
  if (mesh.triangle_count() > 0 && unused == 0) {
    const index_t expected = 2 * static_cast<index_t>(mesh.points.size()) - hull_edges - 2;
    if (mesh.triangle_count() != expected) {
      problem << "triangle count " << mesh.triangle_count() << " differs from 2V - h - 2 = " << expected;
      return problem.str();
    }
  }
  return {};
}

std::vector<index_t> hull_half_edges(const Mesh2& mesh, bool* whole_disk) {
  const index_t n_half = mesh.half_edge_count();
  std::vector<index_t> hull;
  index_t first = 0;
  while (first < n_half && mesh.opp[first] != no_edge) ++first;
  if (whole_disk) *whole_disk = false;
  if (first == n_half) return hull;
  // From a hull half-edge around its head to the hull half-edge leaving it.
  index_t steps = 0;
  for (index_t e = first; steps <= n_half;) {
    hull.push_back(e);
    index_t f = next_edge(e);
    while (mesh.opp[f] != no_edge && ++steps <= n_half) f = next_edge(mesh.opp[f]);
    if (f == first) {
      // One cycle. Euler's formula for a triangulated disk whose vertices
      // are all the points, T = 2V - h - 2, rules out a second cycle (each
      // adds its edges to the count) unless unused points offset it.
      const auto V = static_cast<long long>(mesh.points.size()), h = static_cast<long long>(hull.size());
      if (mesh.triangle_count() == 2 * V - h - 2) {
        if (whole_disk) *whole_disk = true;
        return hull;
      }
      break;
    }
    e = f, ++steps;
  }
  hull.clear();
  for (index_t e = 0; e < n_half; ++e)
    if (mesh.opp[e] == no_edge) hull.push_back(e);
  return hull;
}

double total_area(const Mesh2& mesh) {
  double sum = 0;
  for (index_t t = 0; t < mesh.triangle_count(); ++t)
    sum += 0.5 * signed_area2(mesh.points[mesh.tri[3 * t]], mesh.points[mesh.tri[3 * t + 1]],
                              mesh.points[mesh.tri[3 * t + 2]]);
  return sum;
}

}  // namespace ddt
