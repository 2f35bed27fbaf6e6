// The core's flips against the 3D stack's (mesh3.hpp), the reference they
// are to replace: the same flips offered, and the same arrays after applying.
#include "../test_support3.hpp"
#include "core/check_mesh.hpp"
#include "core/flips.hpp"
#include "core_test_support.hpp"
#include "mesh3.hpp"
#include "tetrahedralization.hpp"

#include <doctest/doctest.h>

#include <random>
#include <set>
#include <utility>

using namespace ddt;

namespace {

core::SimplexMesh<3> to_core(const Mesh3& m) {
  core::SimplexMesh<3> c;
  for (const Point3& p : m.points) c.points.push_back({p.x, p.y, p.z});
  c.cell = m.tet;
  c.opp = m.opp;
  c.free_slots = m.free_slots;
  return c;
}

core::FlipPlan<3> to_core(const FlipPlan& plan) {
  core::FlipPlan<3> c;
  c.removed_count = plan.old_count;
  for (int k = 0; k < plan.old_count; ++k) c.removed[k] = plan.old_tets[k];
  c.inserted_count = plan.new_count;
  for (int k = 0; k < plan.new_count; ++k) c.inserted[k] = plan.new_tets[k];
  return c;
}

// A flip as (removed slots, inserted cells as sorted quadruples).
using FlipSet = std::pair<std::set<index_t>, std::set<std::array<index_t, 4>>>;

template <class Plan>
FlipSet as_set(const index_t* removed, int removed_count, const Plan& inserted, int inserted_count) {
  FlipSet s;
  for (int k = 0; k < removed_count; ++k) s.first.insert(removed[k]);
  for (int k = 0; k < inserted_count; ++k) {
    std::array<index_t, 4> v = inserted[k];
    std::sort(v.begin(), v.end());
    s.second.insert(v);
  }
  return s;
}

// For every face and edge of every tetrahedron, the flips mesh3 plans and
// the flips the core proposes, compared as sets. Returns how many items
// had a flip.
int compare_all_flips(const Mesh3& m) {
  const core::SimplexMesh<3> c = to_core(m);
  int flippable = 0;
  for (index_t t = 0; t < m.slot_count(); ++t) {
    if (!m.is_live(t)) continue;
    for (int i = 0; i < 4; ++i) {
      std::set<FlipSet> reference, core_flips;
      FlipPlan plan;
      if (plan_flip23(m, 4 * t + i, plan))
        reference.insert(as_set(plan.old_tets.data(), plan.old_count, plan.new_tets, plan.new_count));
      core::FlipPlan<3> found[4];
      const int n = core::propose_flip<3>(c, t, 0xFu & ~(1u << i), found, 4);
      for (int p = 0; p < n; ++p)
        core_flips.insert(
            as_set(found[p].removed.data(), found[p].removed_count, found[p].inserted, found[p].inserted_count));
      REQUIRE_MESSAGE(reference == core_flips, "face ", i, " of tetrahedron ", t);
      flippable += !reference.empty();
    }
    for (int k = 0; k < 6; ++k) {
      std::set<FlipSet> reference, core_flips;
      FlipPlan plans[2];
      const index_t a = m.tet[4 * t + edge_vertex[k][0]], b = m.tet[4 * t + edge_vertex[k][1]];
      const int n_ref = plan_edge_flips(m, t, a, b, plans);
      for (int p = 0; p < n_ref; ++p)
        reference.insert(as_set(plans[p].old_tets.data(), plans[p].old_count, plans[p].new_tets, plans[p].new_count));
      core::FlipPlan<3> found[4];
      const unsigned mask = (1u << edge_vertex[k][0]) | (1u << edge_vertex[k][1]);
      const int n = core::propose_flip<3>(c, t, mask, found, 4);
      for (int p = 0; p < n; ++p)
        core_flips.insert(
            as_set(found[p].removed.data(), found[p].removed_count, found[p].inserted, found[p].inserted_count));
      REQUIRE_MESSAGE(reference == core_flips, "edge ", k, " of tetrahedron ", t);
      flippable += !reference.empty();
    }
  }
  return flippable;
}

// Random flips planned by mesh3, applied by mesh3's apply_flip and by the
// core's apply_flip<3> side by side: the arrays must stay equal bit for bit
// (the core relinks exactly as mesh3 does, so it can take its place).
void apply_side_by_side(Mesh3 m, int steps, unsigned seed) {
  core::SimplexMesh<3> c = to_core(m);
  std::mt19937 rng(seed);
  int applied = 0;
  for (int step = 0; step < steps; ++step) {
    std::uniform_int_distribution<index_t> pick(0, m.slot_count() - 1);
    index_t t = pick(rng);
    while (!m.is_live(t)) t = pick(rng);
    FlipPlan plans[3];
    int n = plan_flip23(m, 4 * t + static_cast<int>(rng() % 4), plans[0]) ? 1 : 0;
    const int k = static_cast<int>(rng() % 6);
    n += plan_edge_flips(m, t, m.tet[4 * t + edge_vertex[k][0]], m.tet[4 * t + edge_vertex[k][1]], plans + n);
    if (n == 0) continue;
    const FlipPlan& plan = plans[rng() % n];
    index_t slots_ref[4], slots_core[core::max_flip_cells<3>];
    apply_flip(m, plan, slots_ref);
    core::apply_flip<3>(c, to_core(plan), slots_core);
    ++applied;
    REQUIRE(std::equal(slots_ref, slots_ref + plan.new_count, slots_core));
    REQUIRE(c.cell == m.tet);
    REQUIRE(c.opp == m.opp);
    REQUIRE(c.free_slots == m.free_slots);
  }
  CHECK(check_mesh3(m) == "");
  CHECK(core::check_mesh<3>(c) == "");
  CHECK(applied > steps / 8);  // enough flips to have compared
}

// A mesh far from Delaunay (so with many flippable items): random flips.
Mesh3 scrambled(Mesh3 m, int steps, unsigned seed) {
  std::mt19937 rng(seed);
  for (int step = 0; step < steps; ++step) {
    const index_t t = static_cast<index_t>(rng() % m.slot_count());
    if (!m.is_live(t)) continue;
    FlipPlan plans[2];
    const int k = static_cast<int>(rng() % 6);
    if (plan_edge_flips(m, t, m.tet[4 * t + edge_vertex[k][0]], m.tet[4 * t + edge_vertex[k][1]], plans) > 0)
      apply_flip(m, plans[0]);
    else if (plan_flip23(m, 4 * t + static_cast<int>(rng() % 4), plans[0]))
      apply_flip(m, plans[0]);
  }
  return m;
}

}  // namespace

TEST_CASE("core vs mesh3: the same flips on a voxel grid's tetrahedrization (4-4 and hull 2-2 included)") {
  const Mesh3 m = grid_tetrahedralization(5, 4, 4);
  CHECK(compare_all_flips(m) > 0);
  CHECK(compare_all_flips(scrambled(m, 400, 3)) > 0);
}

TEST_CASE("core vs mesh3: the same flips on random points' Delaunay mesh, before and after random flips") {
  const Mesh3 m = delaunay_tetrahedralization(test::random_points3(150, 12));
  CHECK(compare_all_flips(m) > 0);
  CHECK(compare_all_flips(scrambled(m, 400, 4)) > 0);
}

TEST_CASE("core vs mesh3: apply_flip<3> produces mesh3's tet, opp and free_slots arrays bit for bit") {
  apply_side_by_side(grid_tetrahedralization(5, 4, 4), 400, 5);
  apply_side_by_side(delaunay_tetrahedralization(test::random_points3(150, 13)), 400, 6);
}
