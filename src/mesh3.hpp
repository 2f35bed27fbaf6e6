#pragma once
// ddt::Mesh3 — a 3D tetrahedrization as flat arrays (mesh.hpp's layout, one
// dimension up), and the bistellar flips that change it.
//
// Numbering convention
//   Tetrahedron t owns slots 4t .. 4t+3. tet[4t+i] is its vertex i; slot
//   4t+i also names its FACE i, the triangle opposite vertex i. Vertices are
//   listed positively oriented: orientation(p0, p1, p2, p3) > 0, CGAL's sign,
//   det[p1 - p0, p2 - p0, p3 - p0] > 0.
//   opp[4t+i] = 4u+j when face i of t is face j of u (the same three
//   vertices), or no_face on the convex hull. Invariant: opp[opp[f]] == f.
//   Face i read as (tet[4t + face_vertex[i][0..2]]) has vertex i on its
//   positive side (orientation(face, vertex i) > 0).
//   Local edge k (0..5) joins local vertices edge_vertex[k]:
//   (0,1) (0,2) (0,3) (1,2) (1,3) (2,3).
//   A free slot has tet[4t] == no_vertex; a 3-2 flip frees one, the next
//   2-3 flip reuses it (last freed first), so results are deterministic.
//
// The ring of an edge a-b: the tetrahedra T_0 .. T_{m-1} around it and the
// ring vertices w_0 .. w_m with T_k = {a, b, w_k, w_{k+1}}; T_{k+1} is the
// neighbour of T_k across its face opposite w_k. Closed (interior edge):
// w_m == w_0. Open (hull edge): faces {a, b, w_0} and {a, b, w_m} are hull.
//
// Flips (Edelsbrunner & Shah; the paper's Sect. 4 and Fig. 6). Each replaces
// the tetrahedra of a small region by the other triangulation of its
// vertices; the region and its boundary faces are unchanged.
//
//   2-3: face a b c, shared by      3-2: edge d-e with a closed ring
//        (a,b,c,d) and its               of three, a b c: the inverse.
//        neighbour below, apex e:
//
//              d                                 d
//             /|\                               /|\       .
//            / | \        2-3                  / | \      .
//           a--+--c     ------->              a  |  c     face a b c  ->  edge d-e
//            \ b /      <-------               \ b /      (2 tets)        (3 tets)
//             \|/         3-2                   \|/       .
//              e                                 e
//        before: (a,b,c,d) (a,c,b,e)        after: (a,b,e,d) (b,c,e,d) (c,a,e,d)
//        valid when segment d-e crosses the interior of triangle a b c.
//
//   4-4: edge a-b with a closed ring of four, w0 w1 w2 w3, where a, b, w0,
//        w2 are coplanar (a grid makes this common). Seen in that plane,
//        w1 above it and w3 below, the quadrilateral is re-split:
//
//              a                          a
//            / | \                      /   \        .
//          w0  |  w2       4-4        w0 ----- w2     edge a-b -> edge w0-w2
//            \ | /       ------->      \   /        (4 tets)    (4 tets)
//              b                          b
//
//        before: (a,b,w_k,w_{k+1}) k = 0..3     after: (w0,w2,w1,a) (w2,w0,w1,b)
//                                                      (w2,w0,w3,a) (w0,w2,w3,b)
//        valid when segment w0-w2 crosses segment a-b in their interiors.
//
//   2-2: the same on the hull: edge a-b with an open ring w0 w1 w2 whose
//        hull faces a b w0 and a b w2 are coplanar; after: (w0,w2,w1,a)
//        (w2,w0,w1,b). The boundary case of 4-4 (not in the paper's list;
//        counted separately).
//
// Validity of every flip is decided with CGAL's exact orientation
// predicate: the new tetrahedra are built so that the flip is valid exactly
// when every one is strictly positively oriented (4-4 and 2-2 first require
// their four points exactly coplanar). Why that suffices: the new
// tetrahedra have the same boundary as the old ones (as oriented
// triangles; for 2-2 the two coplanar hull triangles cover the same
// quadrilateral either way), so every point has the same winding number
// (1 inside the region, 0 outside); with all orientations positive, the
// number of new tetrahedra covering a point equals that winding number.

#include "mesh.hpp"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ddt {

inline constexpr index_t no_face = -1;
inline constexpr index_t no_vertex = -1;

constexpr index_t tet_of(index_t f) { return f / 4; }
constexpr int local_of(index_t f) { return f % 4; }

inline constexpr int face_vertex[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
inline constexpr int edge_vertex[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

struct Point3 {
  double x = 0, y = 0, z = 0;
};

struct Mesh3 {
  std::vector<Point3> points;    // #V vertex positions
  std::vector<index_t> tet;      // 4 * #slots vertex ids, positively oriented
  std::vector<index_t> opp;      // 4 * #slots glued faces, no_face on the hull
  std::vector<index_t> free_slots;

  index_t slot_count() const { return static_cast<index_t>(tet.size() / 4); }
  bool is_live(index_t t) const { return tet[4 * static_cast<std::size_t>(t)] != no_vertex; }
  index_t tet_count() const { return slot_count() - static_cast<index_t>(free_slots.size()); }

  // Sets both directions of a glued pair so adjacency is never half-updated.
  void link(index_t f, index_t g) {
    opp[f] = g;
    if (g != no_face) opp[g] = f;
  }
};

// Exact sign of det[q - p, r - p, s - p]: +1 when s lies on the positive
// side of the plane p q r, -1 on the negative side, 0 coplanar (CGAL's
// filtered exact predicate).
int orientation(const Point3& p, const Point3& q, const Point3& r, const Point3& s);

// det[q - p, r - p, s - p] in floating point (6 times the signed volume).
inline double signed_volume6(const Point3& p, const Point3& q, const Point3& r, const Point3& s) {
  const double ux = q.x - p.x, uy = q.y - p.y, uz = q.z - p.z;
  const double vx = r.x - p.x, vy = r.y - p.y, vz = r.z - p.z;
  const double wx = s.x - p.x, wy = s.y - p.y, wz = s.z - p.z;
  return ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx);
}

// The ring of edge a-b around tetrahedron t (which must contain a and b);
// see the convention above. Returns false (and leaves `ring` partly
// filled) when more than max_tets (<= max_ring) tetrahedra surround the
// edge; the walk stops there, so a small max_tets makes it cheap.
inline constexpr int max_ring = 8;
struct EdgeRing {
  index_t a = no_vertex, b = no_vertex;
  bool closed = false;
  int size = 0;                          // m, the number of tetrahedra
  std::array<index_t, max_ring> tets{};  // T_0 .. T_{m-1} (slots)
  std::array<index_t, max_ring + 1> w{};  // w_0 .. w_m
};
bool edge_ring(const Mesh3& mesh, index_t t, index_t a, index_t b, EdgeRing& ring, int max_tets = max_ring);

enum class FlipKind : std::uint8_t { flip23 = 0, flip32 = 1, flip44 = 2, flip22 = 3 };
inline constexpr int flip_kind_count = 4;
const char* flip_kind_name(FlipKind kind);  // "2-3", "3-2", "4-4", "2-2"

// A valid flip, ready to apply: the slots it removes and the positively
// oriented vertex quadruples it creates.
struct FlipPlan {
  FlipKind kind = FlipKind::flip23;
  int old_count = 0;
  std::array<index_t, 4> old_tets{};
  int new_count = 0;
  std::array<std::array<index_t, 4>, 4> new_tets{};
  std::array<index_t, 4> coplanar{};  // 4-4, 2-2: the points that must be coplanar (a, b, w0, w2)
};

// The 2-3 flip of face f (slot 4t+i). False when f is on the hull or the
// flip is not valid (segment d-e misses the triangle's interior).
bool plan_flip23(const Mesh3& mesh, index_t f, FlipPlan& plan);

// The flips that remove the edge a-b of tetrahedron t: 3-2 (closed ring of
// three), 4-4 (closed ring of four, one plan per coplanar diagonal: 0..2),
// 2-2 (open ring of two, coplanar hull faces). Writes the valid ones to
// plans[0..] and returns how many.
int plan_edge_flips(const Mesh3& mesh, index_t t, index_t a, index_t b, FlipPlan plans[2]);

// The fast path for optimizers: the same candidates as plan_flip23 and
// plan_edge_flips, built without exact predicates (vertex order from
// floating-point signs that clearly exceed their rounding error, else
// exact; coplanarity by a tolerant test that never rejects exactly
// coplanar points) and without checking the new tetrahedra. A proposal
// may be invalid: is_valid_flip decides exactly, with the same rule as
// plan_*. So an optimizer can price a flip first and pay for exact
// predicates only when it would take it.
bool propose_flip23(const Mesh3& mesh, index_t f, FlipPlan& plan);
int propose_edge_flips(const Mesh3& mesh, index_t t, index_t a, index_t b, FlipPlan plans[2]);
bool is_valid_flip(const Mesh3& mesh, const FlipPlan& plan);

// Replaces plan.old_tets by plan.new_tets and relinks every face: inside
// the region among the new tetrahedra, on its boundary to the old outside
// neighbours (hull faces stay unlinked). Reuses the old slots first, then
// free slots, then appends. Writes the new slots to new_slots when given.
// Relinks only; precondition: the plan came from plan_flip23 /
// plan_edge_flips on the current mesh.
void apply_flip(Mesh3& mesh, const FlipPlan& plan, index_t* new_slots = nullptr);

// Checks combinatorics and geometry: array sizes; every live tetrahedron
// has four distinct valid vertices and is strictly positively oriented
// (exact); opp symmetric, glued faces have the same three vertices and
// their apexes lie on opposite sides; the hull is a closed surface (every
// hull edge in exactly two hull faces); Euler's relation of a ball,
// V - E + F - T == 1 (V the used vertices); free_slots lists exactly the
// free slots. Returns an empty string when valid, else the first problem.
// Complexity: O(T log T).
std::string check_mesh3(const Mesh3& mesh);

// Total volume of the live tetrahedra.
double total_volume(const Mesh3& mesh);

}  // namespace ddt
