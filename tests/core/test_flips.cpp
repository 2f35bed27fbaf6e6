#include "core/check_mesh.hpp"
#include "core/delaunay.hpp"
#include "core/flips.hpp"
#include "core/predicates.hpp"
#include "core_test_support.hpp"

#include <doctest/doctest.h>

#include <bit>
#include <map>
#include <random>
#include <string>

using namespace ddt;
using namespace ddt::core;
using ddt::core::test::Dim;

namespace {

template <int D>
std::set<CellVertices<D>> cells_of(std::vector<CellVertices<D>> cells) {
  std::set<CellVertices<D>> set;
  for (auto& v : cells) {
    std::sort(v.begin(), v.end());
    set.insert(v);
  }
  return set;
}

std::string reversed(const std::string& name) {
  const auto dash = name.find('-');
  return name.substr(dash + 1) + "-" + name.substr(0, dash);
}

// Flips conv(simplex) with the first plan offered and checks: the name,
// the mesh after (valid, same content, the expected cells), then the
// inverse (offered, named in reverse) restores the cells. Returns the plan.
template <int D>
FlipPlan<D> check_flip_and_back(SimplexMesh<D> mesh, const std::vector<index_t>& simplex, const std::string& name,
                                const std::set<CellVertices<D>>& expected_after, int expected_plans = 1) {
  REQUIRE(check_mesh<D>(mesh) == "");
  const auto before = test::cell_set(mesh);
  const double content = total_content(mesh);
  const auto plans = test::flips_removing(mesh, simplex);
  REQUIRE(static_cast<int>(plans.size()) == expected_plans);
  const FlipPlan<D> plan = plans[0];
  CHECK(flip_name(plan) == name);
  CHECK(test::sorted_ids<D>(plan.a, plan.a_count) == std::vector<index_t>(simplex.begin(), simplex.end()));
  apply_flip(mesh, plan);
  CHECK(check_mesh<D>(mesh) == "");
  CHECK(total_content(mesh) == doctest::Approx(content).epsilon(1e-12));
  CHECK(test::cell_set(mesh) == expected_after);
  CHECK(test::cell_containing(mesh, simplex) == -1);  // conv A is gone
  FlipPlan<D> inverse;
  REQUIRE(test::inverse_flip(mesh, plan, inverse));
  CHECK(flip_name(inverse) == reversed(name));
  apply_flip(mesh, inverse);
  CHECK(check_mesh<D>(mesh) == "");
  CHECK(test::cell_set(mesh) == before);
  return plan;
}

// The 3D ring of four around edge a-b (ids 0, 1), ring vertices 2..5.
SimplexMesh<3> ring_of_four(const Vec<3>& w1) {
  const std::vector<Vec<3>> p = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, w1, {-1, 0, 0}, {0, -1, 0}};
  return mesh_from_cells<3>(p, {{0, 1, 2, 3}, {0, 1, 3, 4}, {0, 1, 4, 5}, {0, 1, 5, 2}});
}

}  // namespace

TEST_CASE("core flips 2D: 2-2 swaps the diagonal of a convex quadrilateral - concave and hull edges do not flip") {
  const std::vector<Vec<2>> p = {{0, 0}, {4, 1}, {5, 5}, {1, 4}};
  const SimplexMesh<2> mesh = mesh_from_cells<2>(p, {{0, 1, 2}, {0, 2, 3}});
  const auto plan = check_flip_and_back(mesh, {0, 2}, "2-2", cells_of<2>({{0, 1, 3}, {1, 2, 3}}));
  CHECK_FALSE(plan.degenerate());
  CHECK(plan.link_count == 1);
  CHECK(test::flips_removing(mesh, {0, 1}).empty());  // hull edge

  std::vector<Vec<2>> concave = p;
  concave[2] = {1.5, 1.5};  // reflex at vertex 2: segment 1-3 passes outside
  CHECK(test::flips_removing(mesh_from_cells<2>(concave, {{0, 1, 2}, {0, 2, 3}}), {0, 2}).empty());
}

TEST_CASE("core flips 3D: 2-3 replaces a triangle pierced by d-e by the edge d-e, and 3-2 returns") {
  const std::vector<Vec<3>> p = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {1, 1, 2}, {1, 1, -1}};
  const SimplexMesh<3> mesh = mesh_from_cells<3>(p, {{0, 1, 2, 3}, {0, 1, 2, 4}});
  const auto plan =
      check_flip_and_back(mesh, {0, 1, 2}, "2-3", cells_of<3>({{0, 1, 3, 4}, {1, 2, 3, 4}, {2, 0, 3, 4}}));
  CHECK(test::sorted_ids<3>(plan.b, plan.b_count) == std::vector<index_t>{3, 4});

  std::vector<Vec<3>> missed = p;
  missed[4] = {4, 4, -1};  // d-e crosses z = 0 at (3, 3): outside the triangle
  CHECK(test::flips_removing(mesh_from_cells<3>(missed, {{0, 1, 2, 3}, {0, 1, 2, 4}}), {0, 1, 2}).empty());
}

TEST_CASE("core flips 3D: 4-4 is the 2D 2-2 of a coplanar a, b, w0, w2 joined with w1 and w3") {
  const SimplexMesh<3> mesh = ring_of_four({0.2, 1, 0.3});  // only a, b, w0, w2 coplanar (y = 0)
  const auto plan =
      check_flip_and_back(mesh, {0, 1}, "4-4", cells_of<3>({{2, 4, 3, 0}, {2, 4, 3, 1}, {2, 4, 5, 0}, {2, 4, 5, 1}}));
  CHECK(plan.degenerate());
  CHECK(plan.circuit_dimension() == 2);
  CHECK(plan.link_count == 2);
  CHECK(test::sorted_ids<3>(plan.b, plan.b_count) == std::vector<index_t>{2, 4});
}

TEST_CASE("core flips 3D: an octahedron's edge has two 4-4 flips, one per coplanar diagonal") {
  SimplexMesh<3> mesh = ring_of_four({0, 1, 0});
  const auto plans = test::flips_removing(mesh, {0, 1});
  REQUIRE(plans.size() == 2);
  std::set<std::vector<index_t>> diagonals;
  for (const auto& plan : plans) {
    CHECK(flip_name(plan) == "4-4");
    diagonals.insert(test::sorted_ids<3>(plan.b, plan.b_count));
    SimplexMesh<3> copy = mesh;
    apply_flip(copy, plan);
    CHECK(check_mesh<3>(copy) == "");
  }
  CHECK(diagonals == std::set<std::vector<index_t>>{{2, 4}, {3, 5}});
}

TEST_CASE("core flips 3D: the hull 2-2 is the 2D 2-2 joined with one vertex - a non-coplanar open ring does not flip") {
  const std::vector<Vec<3>> p = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0.2, 1, 0.3}, {-1, 0, 0}};
  const SimplexMesh<3> mesh = mesh_from_cells<3>(p, {{0, 1, 2, 3}, {0, 1, 3, 4}});
  const auto plan = check_flip_and_back(mesh, {0, 1}, "2-2", cells_of<3>({{2, 4, 3, 0}, {2, 4, 3, 1}}));
  CHECK(plan.degenerate());
  CHECK(plan.link_count == 1);

  std::vector<Vec<3>> bent = p;
  bent[4] = {-1, -0.5, 0};
  CHECK(test::flips_removing(mesh_from_cells<3>(bent, {{0, 1, 2, 3}, {0, 1, 3, 4}}), {0, 1}).empty());
}

TEST_CASE("core flips 4D: 2-4 replaces a tetrahedron pierced by d-e by the edge d-e, and 4-2 returns") {
  const std::vector<Vec<4>> p = {{0, 0, 0, 0}, {3, 0, 0, 0},       {0, 3, 0, 0},
                                 {0, 0, 3, 0}, {0.5, 0.5, 0.5, 1}, {0.5, 0.5, 0.5, -1}};
  const SimplexMesh<4> mesh = mesh_from_cells<4>(p, {{0, 1, 2, 3, 4}, {0, 1, 2, 3, 5}});
  check_flip_and_back(mesh, {0, 1, 2, 3}, "2-4",
                      cells_of<4>({{1, 2, 3, 4, 5}, {0, 2, 3, 4, 5}, {0, 1, 3, 4, 5}, {0, 1, 2, 4, 5}}));
}

TEST_CASE("core flips 4D: 3-3 exchanges two triangles whose interiors cross") {
  // A in the plane x3 = x4 = 0, B in x1 = x2 = 0, both around the origin.
  const std::vector<Vec<4>> p = {{-1, -1, 0, 0}, {2, -1, 0, 0}, {-1, 2, 0, 0},
                                 {0, 0, -1, -1}, {0, 0, 2, -1}, {0, 0, -1, 2}};
  const SimplexMesh<4> mesh = mesh_from_cells<4>(p, {{0, 1, 2, 4, 5}, {0, 1, 2, 3, 5}, {0, 1, 2, 3, 4}});
  const auto plan =
      check_flip_and_back(mesh, {0, 1, 2}, "3-3", cells_of<4>({{1, 2, 3, 4, 5}, {0, 2, 3, 4, 5}, {0, 1, 3, 4, 5}}));
  CHECK_FALSE(plan.degenerate());
}

TEST_CASE("core flips 4D: 6-6 is a planar 2-2 joined with a cycle of three edges") {
  // The quadrilateral a0 b0 a1 b1 in the plane x3 = x4 = 0; the link
  // triangle l0 l1 l2 in x1 = x2 = 0 winds around it.
  const std::vector<Vec<4>> p = {{-1, 0, 0, 0}, {1, 0.2, 0, 0}, {0.1, -1, 0, 0}, {-0.2, 1, 0, 0},
                                 {0, 0, 1, 0},  {0, 0, -1, 1},  {0, 0, -1, -1}};
  std::vector<CellVertices<4>> before, after;
  for (int j = 0; j < 3; ++j) {
    const index_t l = 4 + j, m = 4 + (j + 1) % 3;
    before.push_back({0, 1, 2, l, m});
    before.push_back({0, 1, 3, l, m});
    after.push_back({2, 3, 0, l, m});
    after.push_back({2, 3, 1, l, m});
  }
  const auto plan = check_flip_and_back(mesh_from_cells<4>(p, before), {0, 1}, "6-6", cells_of<4>(after));
  CHECK(plan.circuit_dimension() == 2);
  CHECK(plan.link_count == 3);
}

TEST_CASE("core flips 4D: 4-6 is a 3-flat's 2-3 joined with two vertices, the hull 2-3 with one") {
  // The bipyramid a b c | d e in x4 = 0; link vertices above and below.
  const std::vector<Vec<4>> p = {{0, 0, 0, 0},  {3, 0, 0, 0},       {0, 3, 0, 0},       {1, 1, 2, 0},
                                 {1, 1, -1, 0}, {0.5, 0.5, 0.2, 1}, {0.5, 0.5, 0.2, -1}};
  std::vector<CellVertices<4>> before, after;
  for (index_t link : {5, 6}) {
    before.push_back({0, 1, 2, 3, link});
    before.push_back({0, 1, 2, 4, link});
    for (auto [x, y] : {std::pair{0, 1}, {1, 2}, {2, 0}}) after.push_back({x, y, 3, 4, link});
  }
  const auto plan = check_flip_and_back(mesh_from_cells<4>(p, before), {0, 1, 2}, "4-6", cells_of<4>(after));
  CHECK(plan.circuit_dimension() == 3);
  CHECK(plan.link_count == 2);

  // Only the vertex above: the 3-flat's cells are on the hull.
  const std::vector<CellVertices<4>> hull_before(before.begin(), before.begin() + 2);
  const std::vector<CellVertices<4>> hull_after(after.begin(), after.begin() + 3);
  const auto hull = check_flip_and_back(mesh_from_cells<4>(p, hull_before), {0, 1, 2}, "2-3", cells_of<4>(hull_after));
  CHECK(hull.degenerate());
  CHECK(hull.link_count == 1);
}

namespace {

// Random valid flips: each step picks a random live cell, collects every
// flip removing one of its faces (2 .. D vertices), applies a random one
// and checks the mesh, its content and that the inverse flip is offered
// and restores the cells. Returns the flips applied, by name.
template <int D>
std::map<std::string, int> random_flips(SimplexMesh<D> mesh, int steps, unsigned seed, int& degenerate) {
  std::mt19937 rng(seed);
  const double content = total_content(mesh);
  std::map<std::string, int> kinds;
  degenerate = 0;
  for (int step = 0; step < steps; ++step) {
    std::uniform_int_distribution<index_t> pick(0, mesh.slot_count() - 1);
    index_t c = pick(rng);
    while (!mesh.is_live(c)) c = pick(rng);
    std::vector<FlipPlan<D>> plans;
    for (unsigned mask = 0; mask < (1u << (D + 1)); ++mask) {
      const int bits = std::popcount(mask);
      if (bits < 2 || bits > D) continue;
      FlipPlan<D> found[4];
      const int n = propose_flip<D>(mesh, c, mask, found, 4);
      plans.insert(plans.end(), found, found + n);
    }
    if (plans.empty()) continue;
    const FlipPlan<D> plan = plans[std::uniform_int_distribution<std::size_t>(0, plans.size() - 1)(rng)];
    const auto before = test::cell_set(mesh);
    apply_flip(mesh, plan);
    ++kinds[flip_name(plan)];
    degenerate += plan.degenerate();
    const std::string problem = check_mesh<D>(mesh);
    REQUIRE_MESSAGE(problem == "", "after flip ", step, " (", flip_name(plan), "): ", problem);
    REQUIRE(total_content(mesh) == doctest::Approx(content).epsilon(1e-9));
    if (step % 4 == 0) {
      SimplexMesh<D> back = mesh;
      FlipPlan<D> inverse;
      REQUIRE(test::inverse_flip(back, plan, inverse));
      apply_flip(back, inverse);
      CHECK(check_mesh<D>(back) == "");
      CHECK(test::cell_set(back) == before);
    }
  }
  return kinds;
}

}  // namespace

TEST_CASE_TEMPLATE("core flips: random flips on the Delaunay mesh of random points keep it valid", T, Dim<2>, Dim<3>,
                   Dim<4>) {
  constexpr int D = T::value;
  const SimplexMesh<D> mesh = delaunay<D>(test::random_points<D>(D == 4 ? 50 : 100, 31));
  REQUIRE(check_mesh<D>(mesh) == "");
  int degenerate = 0;
  const auto kinds = random_flips<D>(mesh, D == 4 ? 250 : 300, 17, degenerate);
  CHECK(degenerate == 0);  // general position
  std::vector<std::string> expected;
  if (D == 2) expected = {"2-2"};
  if (D == 3) expected = {"2-3", "3-2"};
  if (D == 4) expected = {"2-4", "3-3", "4-2"};
  for (const auto& name : expected) CHECK_MESSAGE(kinds.count(name) == 1, "no ", name, " flip was taken");
  CHECK(kinds.size() == expected.size());
}

TEST_CASE_TEMPLATE("core flips: random flips on a lattice's Delaunay mesh take the degenerate kinds and stay valid", T,
                   Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  const SimplexMesh<D> mesh = delaunay<D>(test::grid_points<D>(D == 4 ? 3 : 4));
  REQUIRE(check_mesh<D>(mesh) == "");
  int degenerate = 0;
  const auto kinds = random_flips<D>(mesh, 200, 23, degenerate);
  CHECK(degenerate > 0);
  if (D == 3) {
    CHECK(kinds.count("4-4") == 1);
    CHECK(kinds.count("2-2") == 1);
  }
  std::string summary;
  for (const auto& [name, n] : kinds) summary += name + ": " + std::to_string(n) + "  ";
  MESSAGE("lattice flips in ", D, "D: ", summary);
}

TEST_CASE_TEMPLATE("core propose_flip: a vertex or a whole cell is no flip's simplex", T, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  const SimplexMesh<D> mesh = delaunay<D>(test::random_points<D>(30, 4));
  FlipPlan<D> plans[4];
  for (index_t c = 0; c < mesh.slot_count(); ++c) {
    CHECK(propose_flip<D>(mesh, c, 1u, plans, 4) == 0);
    CHECK(propose_flip<D>(mesh, c, (1u << (D + 1)) - 1, plans, 4) == 0);
  }
}

TEST_CASE_TEMPLATE("core flips: every flip of a Delaunay mesh in general position breaks the Delaunay property", T,
                   Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  // The Delaunay triangulation of points in general position is unique, so
  // no other triangulation (in particular no flip of it) is Delaunay.
  const SimplexMesh<D> mesh = delaunay<D>(test::random_points<D>(D == 4 ? 30 : 60, 9));
  REQUIRE(is_delaunay<D>(mesh));
  int flips = 0;
  for (index_t c = 0; c < mesh.slot_count() && flips < 60; ++c)
    for (unsigned mask = 0; mask < (1u << (D + 1)); ++mask) {
      const int bits = std::popcount(mask);
      if (bits < 2 || bits > D) continue;
      FlipPlan<D> plans[4];
      const int n = propose_flip<D>(mesh, c, mask, plans, 4);
      for (int p = 0; p < n; ++p) {
        SimplexMesh<D> copy = mesh;
        apply_flip(copy, plans[p]);
        CHECK_FALSE(is_delaunay<D>(copy));
        ++flips;
      }
    }
  CHECK(flips > 10);
}

TEST_CASE("core flips 2D: Lawson's flips of non-Delaunay edges return a scrambled mesh to the Delaunay triangulation") {
  const auto points = test::random_points<2>(120, 40);
  const SimplexMesh<2> delaunay_mesh = delaunay<2>(points);
  SimplexMesh<2> mesh = delaunay_mesh;
  std::mt19937 rng(2);
  for (int step = 0; step < 400; ++step) {
    const index_t c = static_cast<index_t>(rng() % mesh.slot_count());
    FlipPlan<2> plan;
    if (propose_flip<2>(mesh, c, 0x7u & ~(1u << (rng() % 3)), &plan, 1) == 1) apply_flip(mesh, plan);
  }
  REQUIRE(check_mesh<2>(mesh) == "");
  REQUIRE_FALSE(is_delaunay<2>(mesh));
  // In 2D an edge whose opposite apex is inside the circumcircle always has
  // a convex quadrilateral, so its 2-2 flip is offered.
  bool changed = true;
  int flips = 0;
  while (changed) {
    changed = false;
    for (index_t c = 0; c < mesh.slot_count(); ++c)
      for (int i = 0; i < 3; ++i) {
        const index_t g = mesh.opp[3 * c + i];
        if (g == no_facet || in_sphere<2>(mesh.cell_points(c), mesh.points[mesh.cell[g]]) <= 0) continue;
        FlipPlan<2> plan;
        REQUIRE(propose_flip<2>(mesh, c, 0x7u & ~(1u << i), &plan, 1) == 1);
        apply_flip(mesh, plan);
        changed = true;
        ++flips;
        break;
      }
  }
  CHECK(flips > 0);
  CHECK(check_mesh<2>(mesh) == "");
  CHECK(test::cell_set(mesh) == test::cell_set(delaunay_mesh));
}
