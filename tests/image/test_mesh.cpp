#include "image/mesh.hpp"
#include "test_support.hpp"
#include "image/triangulation.hpp"

#include <doctest/doctest.h>

using namespace ddt;

namespace {
// The smallest case by hand: a unit square split along a-b.
Mesh2 square_quad() {
  Mesh2 m;
  m.points = {{0, 0}, {1, 1}, {0, 1}, {1, 0}};  // a, b, c, d
  m.tri = {0, 1, 2, 1, 0, 3};                   // t0 = (a, b, c), t1 = (b, a, d)
  m.opp = {3, no_edge, no_edge, 0, no_edge, no_edge};
  return m;
}
}  // namespace

TEST_CASE("flip_edge: unit square quad takes the other diagonal") {
  Mesh2 m = square_quad();
  REQUIRE(check_mesh(m).empty());
  REQUIRE(is_flippable(m, 0));
  flip_edge(m, 0);
  CHECK(check_mesh(m).empty());
  CHECK(test::triangle_set(m) == std::set<std::array<index_t, 3>>{{0, 3, 2}, {1, 2, 3}});
  CHECK(m.opp[0] == 3);
  CHECK(m.opp[3] == 0);
}

TEST_CASE("flip_edge: flipping twice restores the triangles") {
  Mesh2 m = delaunay_triangulation(test::random_points(60, 7));
  const auto before = test::triangle_set(m);
  int flipped = 0;
  for (index_t e = 0; e < m.half_edge_count() && flipped < 20; ++e) {
    if (!is_flippable(m, e)) continue;
    flip_edge(m, e);
    REQUIRE(is_flippable(m, e));
    flip_edge(m, e);
    REQUIRE(check_mesh(m).empty());
    CHECK(test::triangle_set(m) == before);
    ++flipped;
  }
  CHECK(flipped == 20);
}

TEST_CASE("is_flippable: a non-convex quad and a hull edge are refused") {
  Mesh2 m;
  // a=(0,0) b=(2,0) c=(1,1) d=(1,0.2)... d must lie right of a->b: use d below.
  m.points = {{0, 0}, {2, 0}, {1, 2}, {1, -0.1}, {1, 0.5}};
  // Reflex case: d is inside triangle (a, b, c)'s mirror... build (a,b,c),(b,a,d) with c near the line.
  m.points = {{0, 0}, {4, 0}, {3, 1}, {5, -1}};  // quad a, d, b, c has a reflex vertex at b
  m.tri = {0, 1, 2, 1, 0, 3};
  m.opp = {3, no_edge, no_edge, 0, no_edge, no_edge};
  REQUIRE(check_mesh(m).empty());
  CHECK_FALSE(is_flippable(m, 0));
  CHECK_FALSE(is_flippable(m, 1));
}

TEST_CASE("flip_edge: thousands of random flips keep the mesh valid") {
  Mesh2 m = delaunay_triangulation(test::random_points(400, 11));
  const index_t triangles = m.triangle_count();
  const double area = total_area(m);
  std::mt19937 rng(3);
  std::uniform_int_distribution<index_t> pick(0, m.half_edge_count() - 1);
  int done = 0;
  for (int i = 0; i < 20000 && done < 5000; ++i) {
    const index_t e = pick(rng);
    if (!is_flippable(m, e)) continue;
    flip_edge(m, e);
    ++done;
    if (done % 500 == 0) REQUIRE(check_mesh(m).empty());
  }
  CHECK(done == 5000);
  CHECK(check_mesh(m).empty());
  CHECK(m.triangle_count() == triangles);
  CHECK(total_area(m) == doctest::Approx(area).epsilon(1e-12));
}

TEST_CASE("check_mesh: reports a broken twin and a clockwise triangle") {
  Mesh2 m = square_quad();
  m.opp[3] = no_edge;
  CHECK_FALSE(check_mesh(m).empty());
  m = square_quad();
  std::swap(m.tri[0], m.tri[1]);
  CHECK_FALSE(check_mesh(m).empty());
}

TEST_CASE("hull_half_edges: walked in order around a triangulation, scanned otherwise") {
  auto scanned = [](const Mesh2& m) {
    std::set<index_t> s;
    for (index_t e = 0; e < m.half_edge_count(); ++e)
      if (m.opp[e] == no_edge) s.insert(e);
    return s;
  };
  for (unsigned seed : {1u, 2u, 3u}) {
    const Mesh2 m = delaunay_triangulation(test::random_points(200, seed));
    bool whole = false;
    const std::vector<index_t> hull = hull_half_edges(m, &whole);
    CHECK(whole);
    CHECK(std::set<index_t>(hull.begin(), hull.end()) == scanned(m));
    REQUIRE(hull.size() == scanned(m).size());
    for (std::size_t i = 0; i < hull.size(); ++i)  // each ends where the next starts
      CHECK(m.tri[next_edge(hull[i])] == m.tri[hull[(i + 1) % hull.size()]]);
  }
  // A point no triangle uses: not every point is a vertex, so no walk claim.
  Mesh2 m = test::grid_mesh(4, 3, true);
  m.points.push_back({10, 10});
  bool whole = true;
  const std::vector<index_t> hull = hull_half_edges(m, &whole);
  CHECK_FALSE(whole);
  CHECK(std::set<index_t>(hull.begin(), hull.end()) == scanned(m));
}
