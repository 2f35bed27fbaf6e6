#include "mesh3.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

namespace ddt {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Kernel::Point_3 cgal_point(const Point3& p) { return {p.x, p.y, p.z}; }

int local_index(const Mesh3& mesh, index_t t, index_t v) {
  for (int i = 0; i < 4; ++i)
    if (mesh.tet[4 * t + i] == v) return i;
  return -1;
}

int orient(const Mesh3& mesh, const std::array<index_t, 4>& q) {
  return orientation(mesh.points[q[0]], mesh.points[q[1]], mesh.points[q[2]], mesh.points[q[3]]);
}

std::array<index_t, 3> sorted_triple(index_t a, index_t b, index_t c) {
  std::array<index_t, 3> s = {a, b, c};
  std::sort(s.begin(), s.end());
  return s;
}

std::array<index_t, 3> face_key(const Mesh3& mesh, index_t f) {
  const index_t t = tet_of(f);
  const int i = local_of(f);
  return sorted_triple(mesh.tet[4 * t + face_vertex[i][0]], mesh.tet[4 * t + face_vertex[i][1]],
                       mesh.tet[4 * t + face_vertex[i][2]]);
}

// A generous bound on the rounding error of signed_volume6(p, q, r, s):
// m the largest coordinate difference from p, c the largest coordinate
// (differences are exact on voxel grids, rounded elsewhere).
double rounding_bound(const Mesh3& mesh, index_t p, index_t q, index_t r, index_t s) {
  const auto& P = mesh.points;
  double m = 0, c = std::max({std::abs(P[p].x), std::abs(P[p].y), std::abs(P[p].z)});
  for (index_t v : {q, r, s}) {
    m = std::max({m, std::abs(P[v].x - P[p].x), std::abs(P[v].y - P[p].y), std::abs(P[v].z - P[p].z)});
    c = std::max({c, std::abs(P[v].x), std::abs(P[v].y), std::abs(P[v].z)});
  }
  return 1e-12 * m * m * (m + c);
}

// Orientation sign for building a plan: exact, or (fast) from floating
// point when the determinant clearly exceeds its rounding error, exact
// otherwise.
int build_sign(const Mesh3& mesh, index_t p, index_t q, index_t r, index_t s, bool exact) {
  const auto& P = mesh.points;
  if (!exact) {
    const double d = signed_volume6(P[p], P[q], P[r], P[s]);
    if (std::abs(d) > rounding_bound(mesh, p, q, r, s)) return d > 0 ? 1 : -1;
  }
  return orientation(P[p], P[q], P[r], P[s]);
}

// Coplanarity of four points: exact, or (fast) a tolerant floating-point
// test that never rejects exactly coplanar points (confirmed exactly later).
bool build_coplanar(const Mesh3& mesh, index_t p, index_t q, index_t r, index_t s, bool exact) {
  const auto& P = mesh.points;
  if (exact) return orientation(P[p], P[q], P[r], P[s]) == 0;
  return std::abs(signed_volume6(P[p], P[q], P[r], P[s])) <= rounding_bound(mesh, p, q, r, s);
}

// The 4-4 (closed ring of four) or 2-2 (open ring of two) flip along the
// diagonal w[k] - w[k+2] of the ring, if a, b, w[k], w[k+2] are coplanar
// and (exact mode) the new tetrahedra are positive.
bool plan_diagonal(const Mesh3& mesh, const EdgeRing& ring, int k, FlipPlan& plan, bool exact) {
  const index_t a = ring.a, b = ring.b;
  index_t w0 = ring.w[k], w1 = ring.w[k + 1], w2 = ring.w[k + 2];
  if (!build_coplanar(mesh, a, b, w0, w2, exact)) return false;
  const int s = build_sign(mesh, w0, w2, w1, a, exact);
  if (s == 0) return false;
  if (s < 0) std::swap(w0, w2);  // mirror: the same split, listed positively
  plan.coplanar = {a, b, w0, w2};
  plan.new_tets[0] = {w0, w2, w1, a};
  plan.new_tets[1] = {w2, w0, w1, b};
  if (ring.closed) {
    const index_t w3 = ring.w[(k + 3) % 4];
    plan.kind = FlipKind::flip44;
    plan.new_tets[2] = {w2, w0, w3, a};
    plan.new_tets[3] = {w0, w2, w3, b};
    plan.new_count = 4;
  } else {
    plan.kind = FlipKind::flip22;
    plan.new_count = 2;
  }
  if (exact)
    for (int n = 1; n < plan.new_count; ++n)
      if (orient(mesh, plan.new_tets[n]) <= 0) return false;
  plan.old_count = ring.size;
  for (int n = 0; n < ring.size; ++n) plan.old_tets[n] = ring.tets[n];
  return true;
}

bool build_flip23(const Mesh3& mesh, index_t f, FlipPlan& plan, bool exact) {
  const index_t g = mesh.opp[f];
  if (g == no_face) return false;
  const index_t t = tet_of(f), u = tet_of(g);
  const int i = local_of(f);
  const index_t a = mesh.tet[4 * t + face_vertex[i][0]], b = mesh.tet[4 * t + face_vertex[i][1]],
                c = mesh.tet[4 * t + face_vertex[i][2]];
  const index_t d = mesh.tet[4 * t + i], e = mesh.tet[4 * u + local_of(g)];
  plan.kind = FlipKind::flip23;
  plan.old_count = 2;
  plan.old_tets[0] = t;
  plan.old_tets[1] = u;
  plan.new_count = 3;
  plan.new_tets[0] = {a, b, e, d};
  plan.new_tets[1] = {b, c, e, d};
  plan.new_tets[2] = {c, a, e, d};
  if (exact)
    for (int n = 0; n < 3; ++n)
      if (orient(mesh, plan.new_tets[n]) <= 0) return false;
  return true;
}

int build_edge_flips(const Mesh3& mesh, index_t t, index_t a, index_t b, FlipPlan plans[2], bool exact) {
  EdgeRing ring;
  if (!edge_ring(mesh, t, a, b, ring, 4)) return 0;  // only rings of 2..4 flip
  int count = 0;
  if (ring.closed && ring.size == 3) {
    // 3-2: triangle w0 w1 w2 with a on one side and b on the other.
    FlipPlan& plan = plans[0];
    index_t w0 = ring.w[0], w1 = ring.w[1], w2 = ring.w[2];
    const int s = build_sign(mesh, w0, w1, w2, a, exact);
    if (s == 0) return 0;
    if (s < 0) std::swap(w1, w2);
    plan.kind = FlipKind::flip32;
    plan.new_count = 2;
    plan.new_tets[0] = {w0, w1, w2, a};
    plan.new_tets[1] = {w0, w2, w1, b};
    if (exact && orient(mesh, plan.new_tets[1]) <= 0) return 0;
    plan.old_count = 3;
    for (int n = 0; n < 3; ++n) plan.old_tets[n] = ring.tets[n];
    return 1;
  }
  if (ring.closed && ring.size == 4) {
    for (int k = 0; k < 2; ++k)
      if (plan_diagonal(mesh, ring, k, plans[count], exact)) ++count;
    return count;
  }
  if (!ring.closed && ring.size == 2) return plan_diagonal(mesh, ring, 0, plans[0], exact) ? 1 : 0;
  return 0;
}

}  // namespace

int orientation(const Point3& p, const Point3& q, const Point3& r, const Point3& s) {
  return static_cast<int>(CGAL::orientation(cgal_point(p), cgal_point(q), cgal_point(r), cgal_point(s)));
}

const char* flip_kind_name(FlipKind kind) {
  switch (kind) {
    case FlipKind::flip23: return "2-3";
    case FlipKind::flip32: return "3-2";
    case FlipKind::flip44: return "4-4";
    case FlipKind::flip22: return "2-2";
  }
  return "?";
}

bool edge_ring(const Mesh3& mesh, index_t t, index_t a, index_t b, EdgeRing& ring, int max_tets) {
  ring.a = a;
  ring.b = b;
  ring.closed = false;
  ring.size = 0;
  const int ia = local_index(mesh, t, a), ib = local_index(mesh, t, b);
  int others[2], n = 0;
  for (int i = 0; i < 4; ++i)
    if (i != ia && i != ib) others[n++] = i;
  // Forward: T_0 = t, w_0 = others[0], w_1 = others[1]; cross the face
  // opposite w_k to reach T_{k+1}.
  index_t fwd_tets[max_ring], fwd_w[max_ring + 1];
  int nf = 0;
  fwd_tets[nf] = t;
  fwd_w[0] = mesh.tet[4 * t + others[0]];
  fwd_w[1] = mesh.tet[4 * t + others[1]];
  ++nf;
  index_t cur = t, behind = fwd_w[0], ahead = fwd_w[1];
  while (true) {
    const index_t f = mesh.opp[4 * cur + local_index(mesh, cur, behind)];
    if (f == no_face) break;
    const index_t next = tet_of(f);
    if (next == t) {
      ring.closed = true;
      break;
    }
    if (nf == max_tets) return false;
    // The vertex of `next` that is not a, b or ahead.
    index_t w = no_vertex;
    for (int i = 0; i < 4; ++i) {
      const index_t v = mesh.tet[4 * next + i];
      if (v != a && v != b && v != ahead) w = v;
    }
    fwd_tets[nf] = next;
    fwd_w[nf + 1] = w;
    ++nf;
    cur = next;
    behind = ahead;
    ahead = w;
  }
  if (ring.closed) {
    ring.size = nf;
    for (int k = 0; k < nf; ++k) ring.tets[k] = fwd_tets[k], ring.w[k] = fwd_w[k];
    ring.w[nf] = fwd_w[0];
    return true;
  }
  // Open: walk backward from t across the face opposite w_1.
  index_t back_tets[max_ring], back_w[max_ring];
  int nb = 0;
  cur = t, behind = fwd_w[1], ahead = fwd_w[0];
  while (true) {
    const index_t f = mesh.opp[4 * cur + local_index(mesh, cur, behind)];
    if (f == no_face) break;
    const index_t next = tet_of(f);
    if (nf + nb == max_tets) return false;
    index_t w = no_vertex;
    for (int i = 0; i < 4; ++i) {
      const index_t v = mesh.tet[4 * next + i];
      if (v != a && v != b && v != ahead) w = v;
    }
    back_tets[nb] = next;
    back_w[nb] = w;
    ++nb;
    cur = next;
    behind = ahead;
    ahead = w;
  }
  // Ring order: back_w[nb-1] .. back_w[0], fwd_w[0] .. fwd_w[nf].
  int k = 0;
  for (int j = nb - 1; j >= 0; --j, ++k) ring.tets[k] = back_tets[j], ring.w[k] = back_w[j];
  for (int j = 0; j < nf; ++j, ++k) ring.tets[k] = fwd_tets[j], ring.w[k] = fwd_w[j];
  ring.w[k] = fwd_w[nf];
  ring.size = k;
  return true;
}

bool plan_flip23(const Mesh3& mesh, index_t f, FlipPlan& plan) { return build_flip23(mesh, f, plan, true); }

int plan_edge_flips(const Mesh3& mesh, index_t t, index_t a, index_t b, FlipPlan plans[2]) {
  return build_edge_flips(mesh, t, a, b, plans, true);
}

bool propose_flip23(const Mesh3& mesh, index_t f, FlipPlan& plan) { return build_flip23(mesh, f, plan, false); }

int propose_edge_flips(const Mesh3& mesh, index_t t, index_t a, index_t b, FlipPlan plans[2]) {
  return build_edge_flips(mesh, t, a, b, plans, false);
}

bool is_valid_flip(const Mesh3& mesh, const FlipPlan& plan) {
  if (plan.kind == FlipKind::flip44 || plan.kind == FlipKind::flip22) {
    const auto& c = plan.coplanar;
    if (orientation(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]], mesh.points[c[3]]) != 0) return false;
  }
  for (int n = 0; n < plan.new_count; ++n)
    if (orient(mesh, plan.new_tets[n]) <= 0) return false;
  return true;
}

void apply_flip(Mesh3& mesh, const FlipPlan& plan, index_t* new_slots) {
  // The region's boundary faces that have an outside neighbour.
  struct Outer {
    std::array<index_t, 3> key;
    index_t neighbour;  // face slot in the outside tetrahedron
  };
  std::array<Outer, 16> outer;
  int n_outer = 0;
  auto is_old = [&](index_t s) {
    for (int k = 0; k < plan.old_count; ++k)
      if (plan.old_tets[k] == s) return true;
    return false;
  };
  for (int k = 0; k < plan.old_count; ++k) {
    const index_t t = plan.old_tets[k];
    for (int i = 0; i < 4; ++i) {
      const index_t g = mesh.opp[4 * t + i];
      if (g == no_face || is_old(tet_of(g))) continue;
      outer[n_outer++] = {face_key(mesh, 4 * t + i), g};
    }
  }

  // Slots: the old ones first, then free ones, then new ones at the end.
  std::array<index_t, 4> slots{};
  for (int k = 0; k < plan.new_count; ++k) {
    if (k < plan.old_count) {
      slots[k] = plan.old_tets[k];
    } else if (!mesh.free_slots.empty()) {
      slots[k] = mesh.free_slots.back();
      mesh.free_slots.pop_back();
    } else {
      slots[k] = mesh.slot_count();
      mesh.tet.insert(mesh.tet.end(), 4, no_vertex);
      mesh.opp.insert(mesh.opp.end(), 4, no_face);
    }
  }
  for (int k = plan.new_count; k < plan.old_count; ++k) {
    const index_t t = plan.old_tets[k];
    for (int i = 0; i < 4; ++i) mesh.tet[4 * t + i] = no_vertex, mesh.opp[4 * t + i] = no_face;
    mesh.free_slots.push_back(t);
  }
  for (int k = 0; k < plan.new_count; ++k)
    for (int i = 0; i < 4; ++i) mesh.tet[4 * slots[k] + i] = plan.new_tets[k][i];

  // Link: each face of a new tetrahedron is inside the region (shared with
  // another new one), on its boundary (the old outside neighbour), or hull.
  std::array<std::array<index_t, 3>, 16> keys;
  for (int k = 0; k < plan.new_count; ++k)
    for (int i = 0; i < 4; ++i) keys[4 * k + i] = face_key(mesh, 4 * slots[k] + i);
  for (int k = 0; k < plan.new_count; ++k)
    for (int i = 0; i < 4; ++i) {
      const int me = 4 * k + i;
      index_t target = no_face;
      bool inner = false;
      for (int other = 0; other < 4 * plan.new_count; ++other)
        if (other / 4 != k && keys[other] == keys[me]) {
          target = 4 * slots[other / 4] + other % 4;
          inner = true;
          break;
        }
      if (!inner)
        for (int o = 0; o < n_outer; ++o)
          if (outer[o].key == keys[me]) {
            target = outer[o].neighbour;
            break;
          }
      mesh.opp[4 * slots[k] + i] = target;
      if (target != no_face && !inner) mesh.opp[target] = 4 * slots[k] + i;
    }
  if (new_slots)
    for (int k = 0; k < plan.new_count; ++k) new_slots[k] = slots[k];
}

std::string check_mesh3(const Mesh3& mesh) {
  std::ostringstream problem;
  if (mesh.tet.size() % 4 != 0 || mesh.opp.size() != mesh.tet.size()) return "array sizes disagree";
  const index_t n_slots = mesh.slot_count();
  const index_t n_points = static_cast<index_t>(mesh.points.size());
  std::vector<char> used(mesh.points.size(), 0);
  std::vector<char> listed_free(n_slots, 0);
  for (index_t t : mesh.free_slots) {
    if (t < 0 || t >= n_slots || mesh.is_live(t) || listed_free[t]) {
      problem << "free slot list names slot " << t << " wrongly";
      return problem.str();
    }
    listed_free[t] = 1;
  }
  long long live = 0, hull_faces = 0;
  std::vector<std::pair<index_t, index_t>> edges;
  std::map<std::pair<index_t, index_t>, int> hull_edges;
  for (index_t t = 0; t < n_slots; ++t) {
    if (!mesh.is_live(t)) {
      if (!listed_free[t]) {
        problem << "slot " << t << " is free but not in free_slots";
        return problem.str();
      }
      continue;
    }
    ++live;
    const index_t* v = &mesh.tet[4 * t];
    for (int i = 0; i < 4; ++i) {
      if (v[i] < 0 || v[i] >= n_points) {
        problem << "tetrahedron " << t << " has vertex " << v[i] << " out of range";
        return problem.str();
      }
      for (int j = 0; j < i; ++j)
        if (v[i] == v[j]) {
          problem << "tetrahedron " << t << " repeats vertex " << v[i];
          return problem.str();
        }
      used[v[i]] = 1;
    }
    const auto& P = mesh.points;
    if (orientation(P[v[0]], P[v[1]], P[v[2]], P[v[3]]) <= 0) {
      problem << "tetrahedron " << t << " is not strictly positively oriented";
      return problem.str();
    }
    for (const auto& e : edge_vertex) edges.emplace_back(std::min(v[e[0]], v[e[1]]), std::max(v[e[0]], v[e[1]]));
    for (int i = 0; i < 4; ++i) {
      const index_t f = 4 * t + i, g = mesh.opp[f];
      if (g == no_face) {
        ++hull_faces;
        for (int k = 0; k < 3; ++k) {
          const index_t p = v[face_vertex[i][k]], q = v[face_vertex[i][(k + 1) % 3]];
          ++hull_edges[{std::min(p, q), std::max(p, q)}];
        }
        continue;
      }
      if (g < 0 || g >= 4 * n_slots || !mesh.is_live(tet_of(g)) || mesh.opp[g] != f) {
        problem << "face " << f << " (tetrahedron " << t << ") is not glued symmetrically";
        return problem.str();
      }
      if (tet_of(g) == t || face_key(mesh, f) != face_key(mesh, g)) {
        problem << "face " << f << " and its neighbour " << g << " have different vertices";
        return problem.str();
      }
      // Each apex on the positive side of its own face: opposite sides.
      const index_t apex = mesh.tet[g];
      const int i0 = face_vertex[i][0], i1 = face_vertex[i][1], i2 = face_vertex[i][2];
      if (orientation(P[v[i0]], P[v[i1]], P[v[i2]], P[apex]) >= 0) {
        problem << "tetrahedra " << t << " and " << tet_of(g) << " lie on the same side of their face";
        return problem.str();
      }
    }
  }
  for (const auto& [edge, count] : hull_edges)
    if (count != 2) {
      problem << "hull edge " << edge.first << "-" << edge.second << " is in " << count << " hull faces";
      return problem.str();
    }
  if (live == 0) return {};
  std::sort(edges.begin(), edges.end());
  const long long n_edges = std::unique(edges.begin(), edges.end()) - edges.begin();
  long long n_vertices = 0;
  for (char u : used) n_vertices += u;
  const long long n_faces = (4 * live + hull_faces) / 2;
  const long long euler = n_vertices - n_edges + n_faces - live;
  if (euler != 1) {
    problem << "Euler characteristic V - E + F - T = " << euler << ", not 1 (" << n_vertices << " - " << n_edges
            << " + " << n_faces << " - " << live << ")";
    return problem.str();
  }
  return {};
}

double total_volume(const Mesh3& mesh) {
  double sum = 0;
  for (index_t t = 0; t < mesh.slot_count(); ++t) {
    if (!mesh.is_live(t)) continue;
    const index_t* v = &mesh.tet[4 * t];
    sum += signed_volume6(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]], mesh.points[v[3]]) / 6.0;
  }
  return sum;
}

}  // namespace ddt
