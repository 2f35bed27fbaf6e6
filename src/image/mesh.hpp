#pragma once
// ddt::Mesh2 — a 2D triangulation as flat arrays (the delaunator layout).
//
// Numbering convention
//   Triangle t owns half-edges 3t, 3t+1, 3t+2. Half-edge e runs from vertex
//   tri[e] to vertex tri[next_edge(e)]; the triangle's vertices are listed
//   counter-clockwise, so its interior lies to the LEFT of each half-edge.
//   opp[e] is the twin half-edge (same edge, other triangle), or no_edge on
//   the convex hull. Invariant: opp[opp[e]] == e.
//
// Flip diagram (flip_edge): e = a->b in t0, its twin f = b->a in t1.
//
//            c                          c
//           / \                        /|\  .
//      ca  /   \  bc              ca  / | \  bc
//         / t0  \                    /  |  \  .
//        a --e-> b        ==>       a t0|t1 b      e = d->c, f = c->d
//         \ <-f /                    \  |  /
//      ad  \ t1/  db              ad  \ | /  db
//           \ /                        \|/
//            d                          d
//
//   Before: t0 = (a, b, c) with slots (e, next e, prev e) = (a->b, b->c, c->a)
//           t1 = (b, a, d) with slots (f, next f, prev f) = (b->a, a->d, d->b)
//   After:  t0 = (d, c, a) with slots (e, next e, prev e) = (d->c, c->a, a->d)
//           t1 = (c, d, b) with slots (f, next f, prev f) = (c->d, d->b, b->c)
//   The outer edges keep their twins (ca, ad, db, bc) but move slots.

#include "core/simplex_mesh.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace ddt {

inline constexpr index_t no_edge = -1;

constexpr index_t tri_of(index_t e) { return e / 3; }
constexpr index_t next_edge(index_t e) { return e % 3 == 2 ? e - 2 : e + 1; }
constexpr index_t prev_edge(index_t e) { return e % 3 == 0 ? e + 2 : e - 1; }

struct Point2 {
  double x = 0, y = 0;
};

struct Mesh2 {
  std::vector<Point2> points;  // #V vertex positions
  std::vector<index_t> tri;    // 3 * #T vertex ids, counter-clockwise
  std::vector<index_t> opp;    // 3 * #T twin half-edges, no_edge on the hull

  index_t triangle_count() const { return static_cast<index_t>(tri.size() / 3); }
  index_t half_edge_count() const { return static_cast<index_t>(tri.size()); }

  // Sets both directions of a twin pair so adjacency is never half-updated.
  void link(index_t a, index_t b) {
    opp[a] = b;
    if (b != no_edge) opp[b] = a;
  }
};

// Exact sign of the orientation of (p, q, r): +1 counter-clockwise, -1
// clockwise, 0 collinear (CGAL's filtered exact predicate).
int orientation(const Point2& p, const Point2& q, const Point2& r);

// Twice the signed area of (p, q, r), in floating point.
inline double signed_area2(const Point2& p, const Point2& q, const Point2& r) {
  return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x);
}

// True when e is interior and the quadrilateral a, d, b, c of the flip
// diagram is strictly convex, i.e. both new triangles are strictly
// counter-clockwise (exact predicates).
bool is_flippable(const Mesh2& mesh, index_t e);

// Replaces edge a-b by c-d as in the diagram. Relinks only; precondition:
// is_flippable(mesh, e).
void flip_edge(Mesh2& mesh, index_t e);

// The same mesh as a core::SimplexMesh<2>: cell t = tri[3t..3t+2], and
// half-edge 3t + k is facet slot 3t + (k + 2) % 3 (the facet opposite
// corner k + 2), so opp maps slot for slot. O(#T + #V).
core::SimplexMesh<2> as_simplex_mesh(const Mesh2& mesh);

// core::check_mesh<2> of as_simplex_mesh(mesh) (twins, strictly
// counter-clockwise triangles, the hull closing up, Euler characteristic
// 1), after the array sizes. Returns an empty string when valid, else a
// description of the first problem.
std::string check_mesh(const Mesh2& mesh);

// The hull's half-edges (those without a twin). When the mesh is a
// triangulated disk whose vertices are all its points (as a triangulation
// of a point set is), they come in order around the hull, found by walking
// it (a few steps per hull vertex after a scan to the first), and
// *whole_disk is set; else they come in half-edge order.
std::vector<index_t> hull_half_edges(const Mesh2& mesh, bool* whole_disk = nullptr);

// Total area of all triangles.
double total_area(const Mesh2& mesh);

}  // namespace ddt
