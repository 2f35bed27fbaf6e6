#include "mesh3.hpp"
#include "tetrahedralization.hpp"
#include "test_support3.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <random>

using namespace ddt;
using test::grid_points3;
using test::tet_set;

TEST_CASE("delaunay_tetrahedralization: a voxel grid gives a valid Delaunay mesh filling the box") {
  const Mesh3 m = delaunay_tetrahedralization(grid_points3(5, 4, 6));
  CHECK(check_mesh3(m) == "");
  CHECK(cgal_is_valid(m));
  CHECK(is_delaunay(m));
  CHECK(total_volume(m) == doctest::Approx(4.0 * 3.0 * 5.0).epsilon(1e-12));
  CHECK(m.free_slots.empty());
}

TEST_CASE("delaunay_tetrahedralization: the grid's cospherical ties do not depend on the insertion order") {
  const std::vector<Point3> points = grid_points3(4, 5, 3);
  const auto reference = tet_set(delaunay_tetrahedralization(points));
  std::mt19937 rng(7);
  for (int round = 0; round < 3; ++round) {
    std::vector<index_t> order(points.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<Point3> shuffled(points.size());
    for (std::size_t i = 0; i < order.size(); ++i) shuffled[i] = points[order[i]];
    Mesh3 m = delaunay_tetrahedralization(shuffled);
    for (auto& v : m.tet) v = order[v];  // back to the original ids
    CHECK(tet_set(m) == reference);
  }
}

TEST_CASE("delaunay_tetrahedralization: arrays are canonical (same mesh, same slots) across runs") {
  const std::vector<Point3> points = test::random_points3(200, 3);
  const Mesh3 a = delaunay_tetrahedralization(points), b = delaunay_tetrahedralization(points);
  CHECK(a.tet == b.tet);
  CHECK(a.opp == b.opp);
  CHECK(check_mesh3(a) == "");
  CHECK(cgal_is_valid(a));
  CHECK(is_delaunay(a));
}

TEST_CASE("delaunay_tetrahedralization: repeated positions use the smallest id; flat input gives no tets") {
  std::vector<Point3> p = grid_points3(3, 3, 3);
  p.push_back(p[4]);
  const Mesh3 m = delaunay_tetrahedralization(p);
  CHECK(check_mesh3(m) == "");
  CHECK(std::find(m.tet.begin(), m.tet.end(), static_cast<index_t>(p.size() - 1)) == m.tet.end());
  const Mesh3 flat = delaunay_tetrahedralization(grid_points3(4, 4, 1));
  CHECK(flat.tet_count() == 0);
}

TEST_CASE("check_mesh3 and cgal_is_valid: catch a wrongly oriented tet and a broken link") {
  Mesh3 m = delaunay_tetrahedralization(grid_points3(3, 3, 3));
  Mesh3 bad = m;
  std::swap(bad.tet[0], bad.tet[1]);
  CHECK(check_mesh3(bad) != "");
  CHECK_FALSE(cgal_is_valid(bad));
  bad = m;
  for (index_t f = 0; f < 4 * bad.slot_count(); ++f)
    if (bad.opp[f] != no_face) {
      bad.opp[bad.opp[f]] = no_face;
      break;
    }
  CHECK(check_mesh3(bad) != "");
}

TEST_CASE("flip 2-3 and 3-2: hand-built bipyramid, and flipping back restores the mesh") {
  // Triangle a b c in z = 0, d above, e below; d-e crosses the triangle.
  const std::vector<Point3> p = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, 1}, {0.6, 0.4, -1}};
  const Mesh3 m0 = test::mesh_from_tets(p, {{0, 1, 2, 3}, {0, 1, 2, 4}});
  REQUIRE(check_mesh3(m0) == "");
  Mesh3 m = m0;
  index_t shared = no_face;
  for (index_t f = 0; f < 8; ++f)
    if (m.opp[f] != no_face) shared = f;
  FlipPlan plan;
  REQUIRE(plan_flip23(m, shared, plan));
  CHECK(plan.kind == FlipKind::flip23);
  apply_flip(m, plan);
  CHECK(m.tet_count() == 3);
  CHECK(check_mesh3(m) == "");
  CHECK(cgal_is_valid(m));
  CHECK(total_volume(m) == doctest::Approx(total_volume(m0)).epsilon(1e-14));

  // The new edge d-e (3, 4) has a closed ring of three: 3-2 restores.
  index_t t = 0;
  auto has = [&](index_t tet, index_t v) { return std::count(m.tet.data() + 4 * tet, m.tet.data() + 4 * tet + 4, v) > 0; };
  while (!(has(t, 3) && has(t, 4))) ++t;
  FlipPlan plans[2];
  REQUIRE(plan_edge_flips(m, t, 3, 4, plans) == 1);
  CHECK(plans[0].kind == FlipKind::flip32);
  apply_flip(m, plans[0]);
  CHECK(check_mesh3(m) == "");
  CHECK(tet_set(m) == tet_set(m0));
  CHECK(m.free_slots.size() == 1);  // the freed slot is reused by the next 2-3
}

TEST_CASE("flip 2-3: refused when the segment misses the triangle or grazes its edge") {
  for (const Point3 e : {Point3{3, 3, -1}, Point3{1, 0, -1} /* d-e through edge a-b's plane */}) {
    const std::vector<Point3> p = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 0, 1}, e};
    const Mesh3 m = test::mesh_from_tets(p, {{0, 1, 2, 3}, {0, 1, 2, 4}});
    REQUIRE(check_mesh3(m) == "");
    FlipPlan plan;
    for (index_t f = 0; f < 8; ++f)
      if (m.opp[f] != no_face) CHECK_FALSE(plan_flip23(m, f, plan));
  }
}

TEST_CASE("flip 4-4: octahedron, both coplanar diagonals offered, result valid") {
  // a, b on the z axis; ring square in z = 0.
  const std::vector<Point3> p = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  const Mesh3 m0 = test::mesh_from_tets(p, {{0, 1, 2, 3}, {0, 1, 3, 4}, {0, 1, 4, 5}, {0, 1, 5, 2}});
  REQUIRE(check_mesh3(m0) == "");
  EdgeRing ring;
  REQUIRE(edge_ring(m0, 0, 0, 1, ring));
  CHECK(ring.closed);
  CHECK(ring.size == 4);
  FlipPlan plans[2];
  REQUIRE(plan_edge_flips(m0, 0, 0, 1, plans) == 2);
  for (int k = 0; k < 2; ++k) {
    Mesh3 m = m0;
    CHECK(plans[k].kind == FlipKind::flip44);
    apply_flip(m, plans[k]);
    CHECK(check_mesh3(m) == "");
    CHECK(cgal_is_valid(m));
    CHECK(m.tet_count() == 4);
    CHECK(total_volume(m) == doctest::Approx(4.0 / 3.0).epsilon(1e-14));
    for (index_t t = 0; t < 4; ++t) {  // edge a-b is gone
      const index_t* corners = m.tet.data() + 4 * t;
      CHECK_FALSE((std::count(corners, corners + 4, 0) && std::count(corners, corners + 4, 1)));
    }
  }
  // Lift one ring vertex out of the plane: that diagonal is no longer a 4-4.
  std::vector<Point3> q = p;
  q[2].y = 0.25;
  const Mesh3 m1 = test::mesh_from_tets(q, {{0, 1, 2, 3}, {0, 1, 3, 4}, {0, 1, 4, 5}, {0, 1, 5, 2}});
  REQUIRE(check_mesh3(m1) == "");
  CHECK(plan_edge_flips(m1, 0, 0, 1, plans) == 1);
}

TEST_CASE("flip 2-2: the hull diagonal of a square pyramid's base") {
  const std::vector<Point3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
  const Mesh3 m0 = test::mesh_from_tets(p, {{0, 1, 2, 4}, {0, 2, 3, 4}});
  REQUIRE(check_mesh3(m0) == "");
  FlipPlan plans[2];
  REQUIRE(plan_edge_flips(m0, 0, 0, 2, plans) == 1);
  CHECK(plans[0].kind == FlipKind::flip22);
  Mesh3 m = m0;
  apply_flip(m, plans[0]);
  CHECK(check_mesh3(m) == "");
  CHECK(cgal_is_valid(m));
  CHECK(total_volume(m) == doctest::Approx(1.0 / 3.0).epsilon(1e-14));
  CHECK(tet_set(m) == tet_set(test::mesh_from_tets(p, {{0, 1, 3, 4}, {1, 2, 3, 4}})));
  // The apex edge 0-4 has an open ring of two too, but its hull faces are not coplanar.
  CHECK(plan_edge_flips(m0, 0, 0, 4, plans) == 0);
}

TEST_CASE("flips: thousands of random valid flips on a grid keep a valid tetrahedrization of the box") {
  Mesh3 m = delaunay_tetrahedralization(grid_points3(6, 5, 5));
  const double volume = total_volume(m);
  std::mt19937 rng(11);
  long long done[flip_kind_count] = {0, 0, 0, 0};
  for (int round = 0; round < 6; ++round) {
    for (int attempt = 0; attempt < 3000; ++attempt) {
      const index_t t = std::uniform_int_distribution<index_t>(0, m.slot_count() - 1)(rng);
      if (!m.is_live(t)) continue;
      const int k = std::uniform_int_distribution<int>(0, 9)(rng);
      FlipPlan plans[2];
      int n = 0;
      if (k < 4) {
        n = plan_flip23(m, 4 * t + k, plans[0]) ? 1 : 0;
      } else {
        const auto& e = edge_vertex[k - 4];
        n = plan_edge_flips(m, t, m.tet[4 * t + e[0]], m.tet[4 * t + e[1]], plans);
      }
      if (n == 0) continue;
      const FlipPlan& plan = plans[std::uniform_int_distribution<int>(0, n - 1)(rng)];
      apply_flip(m, plan);
      ++done[static_cast<int>(plan.kind)];
    }
    REQUIRE(check_mesh3(m) == "");
    CHECK(cgal_is_valid(m));
    CHECK(total_volume(m) == doctest::Approx(volume).epsilon(1e-12));
  }
  for (int k = 0; k < flip_kind_count; ++k) {
    CAPTURE(k);
    CHECK(done[k] > 0);
  }
}

TEST_CASE("propose_* + is_valid_flip: exactly the flips plan_* offers (grid and scattered points)") {
  for (const bool grid : {true, false}) {
    CAPTURE(grid);
    Mesh3 m = grid ? delaunay_tetrahedralization(grid_points3(6, 5, 5))
                   : delaunay_tetrahedralization(test::random_points3(150, 4));
    std::mt19937 rng(2);
    long long compared = 0;
    for (int round = 0; round < 4; ++round) {
      for (index_t t = 0; t < m.slot_count(); ++t) {
        if (!m.is_live(t)) continue;
        for (int k = 0; k < 10; ++k) {
          FlipPlan exact[2], proposed[2];
          int n_exact = 0, n_proposed = 0;
          if (k < 4) {
            n_exact = plan_flip23(m, 4 * t + k, exact[0]) ? 1 : 0;
            n_proposed = propose_flip23(m, 4 * t + k, proposed[0]) ? 1 : 0;
          } else {
            const index_t a = m.tet[4 * t + edge_vertex[k - 4][0]], b = m.tet[4 * t + edge_vertex[k - 4][1]];
            n_exact = plan_edge_flips(m, t, a, b, exact);
            n_proposed = propose_edge_flips(m, t, a, b, proposed);
          }
          std::vector<std::array<index_t, 4>> from_exact, from_proposed;
          for (int p = 0; p < n_exact; ++p)
            for (int q = 0; q < exact[p].new_count; ++q) from_exact.push_back(exact[p].new_tets[q]);
          for (int p = 0; p < n_proposed; ++p)
            if (is_valid_flip(m, proposed[p]))
              for (int q = 0; q < proposed[p].new_count; ++q) from_proposed.push_back(proposed[p].new_tets[q]);
          CHECK(from_exact == from_proposed);
          ++compared;
        }
      }
      // Move away from Delaunay for the next round.
      for (int done = 0, attempt = 0; done < 200 && attempt < 20000; ++attempt) {
        const index_t t = std::uniform_int_distribution<index_t>(0, m.slot_count() - 1)(rng);
        FlipPlan plans[2];
        if (m.is_live(t) && plan_edge_flips(m, t, m.tet[4 * t], m.tet[4 * t + 1], plans) > 0) {
          apply_flip(m, plans[0]);
          ++done;
        } else if (m.is_live(t) && plan_flip23(m, 4 * t, plans[0])) {
          apply_flip(m, plans[0]);
          ++done;
        }
      }
    }
    CHECK(compared > 1000);
    CHECK(check_mesh3(m) == "");
  }
}

TEST_CASE("grid_tetrahedralization: the same arrays as CGAL's Delaunay of the voxel centres") {
  for (const auto& n : std::vector<std::array<int, 3>>{{2, 2, 2}, {3, 2, 2}, {5, 4, 6}, {7, 3, 2}, {6, 6, 6}, {2, 9, 3}}) {
    CAPTURE(n[0]);
    CAPTURE(n[1]);
    CAPTURE(n[2]);
    const Mesh3 fast = grid_tetrahedralization(n[0], n[1], n[2]);
    const Mesh3 cgal = delaunay_tetrahedralization(grid_points3(n[0], n[1], n[2]));
    CHECK(fast.tet == cgal.tet);
    CHECK(fast.opp == cgal.opp);
    CHECK(check_mesh3(fast) == "");
  }
  CHECK(grid_tetrahedralization(4, 4, 1).tet_count() == 0);  // flat: no tetrahedra
}
