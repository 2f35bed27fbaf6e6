#include "core/flips.hpp"

#include "core/predicates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace ddt::core {
namespace {

template <class Array>
bool contains(const Array& list, int count, index_t x) {
  for (int k = 0; k < count; ++k)
    if (list[k] == x) return true;
  return false;
}

// The cells containing every vertex of A, found across the facets that
// contain A (the star of conv A is connected through them). Returns how
// many; -1 when there are more than max_flip_cells<D>, -2 when the walk
// would leave the scope.
// With stop_below >= 0, returns star_has_smaller as soon as a cell of a
// smaller slot is found.
constexpr int star_too_large = -1, star_out_of_scope = -2, star_has_smaller = -3;
template <int D>
int gather_star(const SimplexMesh<D>& mesh, index_t start, const std::array<index_t, D + 1>& a, int a_count,
                std::array<index_t, max_flip_cells<D>>& star, const ReadScope* scope, int cap = max_flip_cells<D>,
                index_t stop_below = -1) {
  int star_count = 0;
  star[star_count++] = start;
  for (int k = 0; k < star_count; ++k) {
    const index_t c = star[k];
    for (int i = 0; i <= D; ++i) {
      if (contains(a, a_count, mesh.vertex(c, i))) continue;  // facet i misses that vertex of A
      const index_t g = mesh.opp[(D + 1) * c + i];
      if (g == no_facet) continue;
      const index_t next = cell_of<D>(g);
      if (contains(star, star_count, next)) continue;
      if (scope && !scope->reads(next)) return star_out_of_scope;
      if (next < stop_below) return star_has_smaller;
      if (star_count == cap) return star_too_large;
      star[star_count++] = next;
    }
  }
  return star_count;
}

// The most cells a flip removing a simplex of a vertices can remove. The
// circuit A u B spans a k-flat, a <= k <= D (|B| = k + 2 - a >= 2), and the
// flip removes |B| cells per link simplex: one link (none) when k = D; when
// k = D - 1 the links are single vertices on either side of the hyperplane,
// at most two; lower circuits (k <= D - 2, possible when a <= D - 2) have
// links of any size. So 2 for a facet, 4 for an edge in 3D.
template <int D>
constexpr int largest_star(int a) {
  return a <= D - 2 ? max_flip_cells<D> : std::max(D + 2 - a, 2 * (D + 1 - a));
}

// With the circuit (A, B) fixed, checks that the star is exactly
// {(A u B \ b) u L : b in B, L in Links} and fills the plan's cells.
template <int D>
bool build_plan(const SimplexMesh<D>& mesh, const std::array<index_t, max_flip_cells<D>>& star, int star_count,
                FlipPlan<D>& plan, bool lattice) {
  constexpr int cap = max_flip_cells<D>;
  const int link_size = D - plan.circuit_dimension();  // vertices per link simplex
  std::array<std::array<index_t, D + 1>, cap> links;  // the first link_count are set
  std::array<unsigned, cap> missing_b;  // per link: bit j when (A u B \ b_j) u L is present
  int link_count = 0;
  for (int s = 0; s < star_count; ++s) {
    std::array<index_t, D + 1> rest;  // the link vertices, then sentinels (sorted last)
    rest.fill(std::numeric_limits<index_t>::max());
    int rest_count = 0, in_b = 0;
    unsigned present = 0;
    for (int i = 0; i <= D; ++i) {
      const index_t v = mesh.vertex(star[s], i);
      if (contains(plan.a, plan.a_count, v)) continue;
      bool is_b = false;
      for (int j = 0; j < plan.b_count; ++j)
        if (plan.b[j] == v) present |= 1u << j, is_b = true;
      if (is_b)
        ++in_b;
      else
        rest[rest_count++] = v;
    }
    if (in_b != plan.b_count - 1 || rest_count != link_size) return false;
    std::sort(rest.begin(), rest.end());
    const unsigned missing = ((1u << plan.b_count) - 1) & ~present;
    int l = 0;
    while (l < link_count && !same_ids(links[l], rest)) ++l;
    if (l == link_count) links[link_count++] = rest, missing_b[l] = 0;
    if (missing_b[l] & missing) return false;  // the same cell twice: not a mesh
    missing_b[l] |= missing;
  }
  for (int l = 0; l < link_count; ++l)
    if (missing_b[l] != (1u << plan.b_count) - 1) return false;  // T_B * L incomplete: not this flip
  if (plan.a_count * link_count > cap) return false;

  double factorial = 1;  // as simplex_content divides
  for (int i = 2; i <= D; ++i) factorial *= i;
  plan.contents_known = lattice;
  plan.link_count = link_count;
  plan.removed_count = star_count;
  for (int s = 0; s < star_count; ++s) plan.removed[s] = star[s];
  plan.inserted_count = 0;
  for (int l = 0; l < link_count; ++l)
    for (int skip = 0; skip < plan.a_count; ++skip) {
      CellVertices<D> v;
      int n = 0;
      for (int j = 0; j < plan.a_count; ++j)
        if (j != skip) v[n++] = plan.a[j];
      for (int j = 0; j < plan.b_count; ++j) v[n++] = plan.b[j];
      for (int j = 0; j < link_size; ++j) v[n++] = links[l][j];
      int o;
      if (lattice) {
        std::array<Vec<D>, D + 1> p;
        for (int i = 0; i <= D; ++i) p[i] = mesh.points[v[i]];
        const double det = lattice_det<D>(p);
        o = (det > 0) - (det < 0);
        plan.inserted_content[plan.inserted_count] = std::abs(det) / factorial;
      } else {
        o = orient_ids<D>(mesh.points, v);
      }
      if (o == 0) return false;  // unreachable in exact arithmetic: (A, B) is a Radon partition
      if (o < 0) std::swap(v[0], v[1]);
      plan.inserted[plan.inserted_count++] = v;
    }
  return true;
}

// The Radon signs (radon_partition's l_i = (-1)^i orient(S \ s_i)) of S =
// the start cell's vertices plus y, the apex across its facet x, when the
// vertices in a_mask form exactly one side; false otherwise. Two signs need
// no predicate: S \ y is the start cell, positive, so l_y = (-1)^(D+1);
// S \ s_x is the neighbour's vertex set with y moved from place x to the
// end, D - x transpositions from a negative order, so l_x = l_y. So x and
// y are on B's side, and A's vertices are tested first to reject early.
template <int D>
bool a_is_a_side(const std::array<Vec<D>, D + 2>& s, int x, unsigned a_mask, std::array<int, D + 2>& sign,
                 bool lattice) {
  const int b_side = (D % 2 == 0) ? -1 : 1;
  sign[D + 1] = b_side;
  sign[x] = b_side;
  auto lambda = [&](int i) {
    std::array<Vec<D>, D + 1> rest;
    for (int j = 0, n = 0; j < D + 2; ++j)
      if (j != i) rest[n++] = s[j];
    const int o = orient<D>(rest, lattice);
    return (i % 2 == 0) ? o : -o;
  };
  for (int i = 0; i <= D; ++i)
    if (a_mask & (1u << i)) {
      sign[i] = lambda(i);
      if (sign[i] != -b_side) return false;
    }
  for (int i = 0; i <= D; ++i)
    if (!(a_mask & (1u << i)) && i != x) {
      sign[i] = lambda(i);
      if (sign[i] == -b_side) return false;  // on A's side but not in A
    }
  return true;
}

}  // namespace

template <int D>
std::string flip_name(const FlipPlan<D>& plan) {
  return std::to_string(plan.removed_count) + "-" + std::to_string(plan.inserted_count);
}

template <int D>
bool first_of_star(const SimplexMesh<D>& mesh, index_t start, unsigned simplex_mask) {
  std::array<index_t, D + 1> a{};
  int a_count = 0;
  for (int i = 0; i <= D; ++i)
    if (simplex_mask & (1u << i)) a[a_count++] = mesh.vertex(start, i);
  std::array<index_t, max_flip_cells<D>> star;
  return gather_star(mesh, start, a, a_count, star, nullptr, max_flip_cells<D>, start) > 0;
}

template <int D>
int propose_flip(const SimplexMesh<D>& mesh, index_t start, unsigned simplex_mask, FlipPlan<D>* plans, int max_plans,
                 const ProposalOptions& options) {
  const ReadScope* scope = options.scope;
  FlipPlan<D> plan;
  for (int i = 0; i <= D; ++i)
    if (simplex_mask & (1u << i)) plan.a[plan.a_count++] = mesh.vertex(start, i);
  if (plan.a_count < 2 || plan.a_count > D) return 0;

  std::array<index_t, max_flip_cells<D>> star;
  int star_count = 0;  // gathered when a circuit first passes (most items fail before)
  if (plan.a_count < D && largest_star<D>(plan.a_count) < max_flip_cells<D>) {
    // A star too large for any flip is rejected before any predicate.
    star_count = gather_star(mesh, start, plan.a, plan.a_count, star, scope, largest_star<D>(plan.a_count));
    if (star_count == star_too_large) return 0;
    if (star_count == star_out_of_scope) return -1;
  }

  // Each apex y across a facet of the start cell that contains A closes a
  // set of D + 2 points; a valid flip's circuit is the dependence of one of
  // them (the start cell (A u B \ b0) u L0 plus y = b0).
  const CellVertices<D> start_vertices = mesh.cell_vertices(start);
  int count = 0;
  for (int x = 0; x <= D && count < max_plans; ++x) {
    if (simplex_mask & (1u << x)) continue;
    const index_t g = mesh.opp[(D + 1) * start + x];
    if (g == no_facet) continue;
    if (scope && !scope->reads(cell_of<D>(g))) return -1;
    std::array<index_t, D + 2> ids;
    std::array<Vec<D>, D + 2> points;
    for (int i = 0; i <= D; ++i) ids[i] = start_vertices[i];
    ids[D + 1] = mesh.apex_across((D + 1) * start + x);
    for (int i = 0; i < D + 2; ++i) points[i] = mesh.points[ids[i]];
    std::array<int, D + 2> sign;
    if (!a_is_a_side<D>(points, x, simplex_mask, sign, options.lattice_exact)) continue;
    plan.b_count = 0;
    for (int i = 0; i < D + 2; ++i)
      if (sign[i] == sign[D + 1]) plan.b[plan.b_count++] = ids[i];
    if (plan.b_count < 2) continue;
    std::sort(plan.b.begin(), plan.b.begin() + plan.b_count);
    bool seen = false;
    for (int p = 0; p < count; ++p)
      if (plans[p].b_count == plan.b_count &&
          std::equal(plan.b.begin(), plan.b.begin() + plan.b_count, plans[p].b.begin()))
        seen = true;
    if (seen) continue;
    if (star_count == 0) {
      star_count = gather_star(mesh, start, plan.a, plan.a_count, star, scope);
      if (star_count == star_too_large) return 0;
      if (star_count == star_out_of_scope) return -1;
    }
    if (build_plan(mesh, star, star_count, plan, options.lattice_exact)) plans[count++] = plan;
  }
  return count;
}

template <int D>
void apply_flip(SimplexMesh<D>& mesh, const FlipPlan<D>& plan, index_t* new_slots, std::vector<index_t>* free_slots) {
  constexpr int cap = max_flip_cells<D>;
  std::vector<index_t>& pool = free_slots ? *free_slots : mesh.free_slots;
  // The region's boundary facets that have an outside neighbour.
  struct Outer {
    FacetKey<D> key;
    index_t neighbour;  // facet slot in the outside cell
  };
  std::array<Outer, cap*(D + 1)> outer;
  int outer_count = 0;
  for (int k = 0; k < plan.removed_count; ++k) {
    const index_t c = plan.removed[k];
    for (int i = 0; i <= D; ++i) {
      const index_t g = mesh.opp[(D + 1) * c + i];
      if (g == no_facet || contains(plan.removed, plan.removed_count, cell_of<D>(g))) continue;
      outer[outer_count++] = {facet_key(mesh, (D + 1) * c + i), g};
    }
  }

  // Slots: the removed ones first, then free ones, then new ones at the end.
  std::array<index_t, cap> slots{};
  for (int k = 0; k < plan.inserted_count; ++k) {
    if (k < plan.removed_count) {
      slots[k] = plan.removed[k];
    } else if (!pool.empty()) {
      slots[k] = pool.back();
      pool.pop_back();
    } else {
      slots[k] = mesh.slot_count();
      mesh.cell.insert(mesh.cell.end(), D + 1, no_vertex);
      mesh.opp.insert(mesh.opp.end(), D + 1, no_facet);
    }
  }
  for (int k = plan.inserted_count; k < plan.removed_count; ++k) {
    const index_t c = plan.removed[k];
    for (int i = 0; i <= D; ++i) mesh.cell[(D + 1) * c + i] = no_vertex, mesh.opp[(D + 1) * c + i] = no_facet;
    pool.push_back(c);
  }
  for (int k = 0; k < plan.inserted_count; ++k)
    for (int i = 0; i <= D; ++i) mesh.cell[(D + 1) * slots[k] + i] = plan.inserted[k][i];

  // Each facet of a new cell is inside the region (shared with another new
  // cell), on its boundary (the old outside neighbour), or on the hull.
  std::array<FacetKey<D>, cap*(D + 1)> keys;
  const int n_keys = (D + 1) * plan.inserted_count;
  for (int n = 0; n < n_keys; ++n) keys[n] = facet_key(mesh, (D + 1) * slots[n / (D + 1)] + n % (D + 1));
  // The vertex x opposite a new cell's facet says where its partner is (by
  // the order of plan.inserted). x in A: the cell of the same link without
  // x, across its facet opposite this cell's own missing vertex of A. x in
  // B: no new cell (every new cell holds all of B), so the old outside
  // neighbour or the hull. x in a link: another link's cell, found by its
  // key. A facet is shared by at most two cells, so this finds what a
  // search of every key would.
  for (int me = 0; me < n_keys; ++me) {
    const int k = me / (D + 1);
    const index_t f = (D + 1) * slots[k] + me % (D + 1);
    const index_t x = plan.inserted[k][me % (D + 1)];
    index_t target = no_facet;
    bool inner = false;
    int in_a = 0;
    while (in_a < plan.a_count && plan.a[in_a] != x) ++in_a;
    if (in_a < plan.a_count) {
      const int partner = k - k % plan.a_count + in_a;
      const index_t missing = plan.a[k % plan.a_count];
      int i = 0;
      while (plan.inserted[partner][i] != missing) ++i;
      target = (D + 1) * slots[partner] + i;
      inner = true;
    } else if (!contains(plan.b, plan.b_count, x)) {
      for (int other = 0; other < n_keys && !inner; ++other)
        if (other / (D + 1) != k && same_ids(keys[other], keys[me])) {
          target = (D + 1) * slots[other / (D + 1)] + other % (D + 1);
          inner = true;
        }
    }
    if (!inner)
      for (int o = 0; o < outer_count; ++o)
        if (same_ids(outer[o].key, keys[me])) {
          target = outer[o].neighbour;
          break;
        }
    mesh.opp[f] = target;
    if (target != no_facet && !inner) mesh.opp[target] = f;
  }
  if (new_slots)
    for (int k = 0; k < plan.inserted_count; ++k) new_slots[k] = slots[k];
}

#define DDT_CORE_INSTANTIATE(D)                                                              \
  template std::string flip_name<D>(const FlipPlan<D>&);                                     \
  template int propose_flip<D>(const SimplexMesh<D>&, index_t, unsigned, FlipPlan<D>*, int, const ProposalOptions&); \
  template bool first_of_star<D>(const SimplexMesh<D>&, index_t, unsigned);                                      \
  template void apply_flip<D>(SimplexMesh<D>&, const FlipPlan<D>&, index_t*, std::vector<index_t>*);
DDT_CORE_INSTANTIATE(2)
DDT_CORE_INSTANTIATE(3)
DDT_CORE_INSTANTIATE(4)
#undef DDT_CORE_INSTANTIATE

}  // namespace ddt::core
