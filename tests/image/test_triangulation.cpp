#include "test_support.hpp"
#include "image/triangulation.hpp"

#include <doctest/doctest.h>

using namespace ddt;

TEST_CASE("delaunay_triangulation: a pixel grid gives 2(w-1)(h-1) triangles of area 1/2") {
  Mesh2 m = delaunay_triangulation(test::grid_points(7, 5));
  REQUIRE(check_mesh(m).empty());
  CHECK(m.triangle_count() == 2 * 6 * 4);
  for (index_t t = 0; t < m.triangle_count(); ++t)
    CHECK(signed_area2(m.points[m.tri[3 * t]], m.points[m.tri[3 * t + 1]], m.points[m.tri[3 * t + 2]]) ==
          doctest::Approx(1.0));
  CHECK(is_delaunay(m));
}

TEST_CASE("delaunay_triangulation: empty-circle property on random points") {
  for (unsigned seed : {1u, 2u, 3u}) {
    Mesh2 m = delaunay_triangulation(test::random_points(500, seed));
    REQUIRE(check_mesh(m).empty());
    CHECK(is_delaunay(m));
  }
}

TEST_CASE("delaunay_triangulation: cocircular ties match naive Lawson from either grid diagonal") {
  // The perturbed criterion defines one triangulation; reaching it by plain
  // Lawson flips from both uniform grid splittings must give CGAL's answer.
  const int w = 9, h = 8;
  const Mesh2 reference = delaunay_triangulation(test::grid_points(w, h));
  REQUIRE(check_mesh(reference).empty());
  for (bool slash : {true, false}) {
    Mesh2 m = test::grid_mesh(w, h, slash);
    REQUIRE(check_mesh(m).empty());
    for (bool changed = true; changed;) {
      changed = false;
      for (index_t e = 0; e < m.half_edge_count(); ++e)
        if (violates_perturbed_delaunay(m, e) && is_flippable(m, e)) {
          flip_edge(m, e);
          changed = true;
        }
    }
    CHECK(check_mesh(m).empty());
    CHECK(test::triangle_set(m) == test::triangle_set(reference));
  }
  for (index_t e = 0; e < reference.half_edge_count(); ++e) CHECK_FALSE(violates_perturbed_delaunay(reference, e));
}

TEST_CASE("delaunay_triangulation: a pixel grid (the core's repeated cell) gives CGAL's arrays with the tie-break") {
  // A repeated last point makes the same set no lattice, so it goes through
  // CGAL and resolve_ties; the copy stays unreferenced, the arrays agree.
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{2, 2}, {2, 9}, {9, 2}, {40, 31}, {33, 64}}) {
    CAPTURE(w);
    CAPTURE(h);
    std::vector<Point2> points = test::grid_points(w, h);
    const Mesh2 grid = delaunay_triangulation(points);
    points.push_back(points.back());
    const Mesh2 general = delaunay_triangulation(points);
    CHECK(grid.tri == general.tri);
    CHECK(grid.opp == general.opp);
    CHECK(check_mesh(grid).empty());
    CHECK(grid.triangle_count() == 2 * (w - 1) * (h - 1));
  }
}

TEST_CASE("delaunay_triangulation: perturbed tie-break is antisymmetric on a square") {
  // One of the two diagonals of a cocircular square violates, never both.
  std::vector<Point2> p = {{0, 0}, {1, 1}, {0, 1}, {1, 0}};
  Mesh2 m = test::mesh_from_triangles(p, {{0, 1, 2}, {1, 0, 3}});
  const bool first = violates_perturbed_delaunay(m, 0);
  flip_edge(m, 0);
  CHECK(violates_perturbed_delaunay(m, 0) != first);
}

TEST_CASE("delaunay_triangulation: collinear and tiny inputs give no triangles") {
  CHECK(delaunay_triangulation({}).triangle_count() == 0);
  CHECK(delaunay_triangulation({{0.5, 0.5}}).triangle_count() == 0);
  CHECK(delaunay_triangulation(test::grid_points(10, 1)).triangle_count() == 0);
  CHECK(delaunay_triangulation(test::grid_points(1, 10)).triangle_count() == 0);
  Mesh2 two_rows = delaunay_triangulation(test::grid_points(10, 2));
  CHECK(two_rows.triangle_count() == 18);
  CHECK(check_mesh(two_rows).empty());
}

TEST_CASE("delaunay_triangulation: repeated points are used once") {
  std::vector<Point2> p = {{0, 0}, {1, 0}, {0, 1}, {1, 0}, {1, 1}};
  Mesh2 m = delaunay_triangulation(p);
  CHECK(m.triangle_count() == 2);
  for (index_t v : m.tri) CHECK(v != 3);
}
