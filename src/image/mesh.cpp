#include "image/mesh.hpp"

#include "core/check_mesh.hpp"
#include "core/predicates.hpp"


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

core::SimplexMesh<2> as_simplex_mesh(const Mesh2& mesh) {
  core::SimplexMesh<2> out;
  out.points.reserve(mesh.points.size());
  for (const Point2& p : mesh.points) out.points.push_back({p.x, p.y});
  out.cell = mesh.tri;
  out.opp.resize(mesh.opp.size());
  // Half-edge 3t + k lies on the facet opposite corner k + 2; ids out of
  // range stay out of range, for check_mesh to name.
  auto slot = [](index_t h) { return h < 0 ? h : 3 * tri_of(h) + (h % 3 + 2) % 3; };
  for (index_t h = 0; h < mesh.half_edge_count(); ++h) out.opp[slot(h)] = slot(mesh.opp[h]);
  return out;
}

std::string check_mesh(const Mesh2& mesh) {
  if (mesh.tri.size() % 3 != 0 || mesh.opp.size() != mesh.tri.size()) return "array sizes disagree";
  return core::check_mesh<2>(as_simplex_mesh(mesh));
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
