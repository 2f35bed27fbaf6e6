#include "test_support.hpp"
#include "optimizer3.hpp"
#include "tetrahedralization.hpp"
#include "test_support3.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace ddt;

namespace {

using test::random_values;

// A sphere of radius r around c, box-filtered over each voxel (4^3 sub-samples).
std::vector<float> ball_values(int n, double r) {
  const double c = n / 2.0 + 0.1;
  std::vector<float> v;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        int inside = 0;
        for (int k = 0; k < 64; ++k) {
          const double px = x + (k % 4 + 0.5) / 4, py = y + (k / 4 % 4 + 0.5) / 4, pz = z + (k / 16 + 0.5) / 4;
          inside += (px - c) * (px - c) + (py - c) * (py - c) + (pz - c) * (pz - c) < r * r;
        }
        v.push_back(inside / 64.0f);
      }
  return v;
}

// Every valid flip of the mesh, with the item that offers it.
std::vector<FlipPlan> some_flips(const Mesh3& m, int wanted) {
  std::vector<FlipPlan> out;
  for (index_t t = 0; t < m.slot_count() && static_cast<int>(out.size()) < wanted; ++t) {
    if (!m.is_live(t)) continue;
    for (int k = 0; k < 10; ++k) {
      FlipPlan plans[2];
      int n = 0;
      if (k < 4) {
        n = plan_flip23(m, 4 * t + k, plans[0]) ? 1 : 0;
      } else {
        n = plan_edge_flips(m, t, m.tet[4 * t + edge_vertex[k - 4][0]], m.tet[4 * t + edge_vertex[k - 4][1]], plans);
      }
      for (int p = 0; p < n; ++p) out.push_back(plans[p]);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("flip_costs (3D): the local gain equals the change of the total, for every cost and flip kind") {
  for (const CostFunction& cost : cost_functions()) {
    const std::string name = cost.name;
    CAPTURE(name);
    for (const bool grid : {false, true}) {
      CAPTURE(grid);
      const Mesh3 m0 = grid ? delaunay_tetrahedralization(test::grid_points3(5, 4, 4))
                            : delaunay_tetrahedralization(test::random_points3(120, 5));
      const std::vector<float> values = random_values(m0.points.size(), 2, 6);
      const std::vector<FlipPlan> flips = some_flips(m0, 400);
      int kinds[flip_kind_count] = {0, 0, 0, 0};
      const double before = total_cost(m0, values, 2, cost);
      for (std::size_t i = 0; i < flips.size(); i += 3) {
        Mesh3 m = m0;
        const LocalCosts fc = flip_costs(m, values, 2, cost, flips[i]);
        apply_flip(m, flips[i]);
        const double after = total_cost(m, values, 2, cost);
        CHECK(before - after == doctest::Approx(fc.gain()).epsilon(1e-9).scale(std::abs(before)));
        ++kinds[static_cast<int>(flips[i].kind)];
      }
      // On a Delaunay grid every 2-3 is degenerate (d-e meets an edge).
      if (!grid) CHECK(kinds[0] > 0);
      CHECK(kinds[1] + kinds[2] + kinds[3] > 0);
    }
  }
}

TEST_CASE("optimize_lawson (3D): no accepted flip raises the cost; ends valid, locally optimal, same volume") {
  for (const CostFunction& cost : cost_functions()) {
    const std::string name = cost.name;
    CAPTURE(name);
    Mesh3 m = delaunay_tetrahedralization(test::grid_points3(8, 8, 8));
    const double volume = total_volume(m);
    const std::vector<float> values = ball_values(8, 2.7);
    std::vector<double> totals;
    Lawson3Options opt;
    opt.on_iteration = [&](int, const FlipCounts&, double total) { totals.push_back(total); };
    const Lawson3Stats st = optimize_lawson(m, values, 1, cost, opt);
    CHECK(st.flips.total() > 0);
    CHECK(st.cost_after < st.cost_before);
    double previous = st.cost_before;
    for (double t : totals) {
      CHECK(t <= previous);
      previous = t;
    }
    CHECK(totals.back() == doctest::Approx(st.cost_after).epsilon(1e-9));
    CHECK(check_mesh3(m) == "");
    CHECK(cgal_is_valid(m));
    CHECK(total_volume(m) == doctest::Approx(volume).epsilon(1e-12));
    // Locally optimal: no flip left that lowers the cost beyond the tolerance.
    for (const FlipPlan& plan : some_flips(m, 1 << 30)) {
      CHECK_FALSE(flip_costs(m, values, 1, cost, plan).improves(1e-9));
    }
  }
}

TEST_CASE("optimize_lawson (3D): every single flip lowers the total (checked flip by flip)") {
  // Re-run with a cost check after each iteration on a small random set.
  Mesh3 m = delaunay_tetrahedralization(test::random_points3(150, 12));
  const std::vector<float> values = random_values(m.points.size(), 1, 13);
  const CostFunction& cost = find_cost("variance");
  double last = total_cost(m, values, 1, cost);
  Lawson3Options opt;
  opt.max_iterations = 1;
  for (int round = 0; round < 20; ++round) {
    const Lawson3Stats st = optimize_lawson(m, values, 1, cost, opt);
    CHECK(st.cost_after <= last);
    last = st.cost_after;
    if (st.flips.total() == 0) break;
  }
  CHECK(check_mesh3(m) == "");
}

TEST_CASE("optimize_lawson (3D): a linear field makes no sederberg flips; a constant field none at all") {
  Mesh3 m = delaunay_tetrahedralization(test::grid_points3(6, 5, 4));
  const Mesh3 m0 = m;
  std::vector<float> linear, constant(m.points.size(), 0.25f);
  for (const Point3& p : m.points) linear.push_back(static_cast<float>(0.1 * p.x - 0.05 * p.y + 0.2 * p.z));
  CHECK(optimize_lawson(m, linear, 1, find_cost("sederberg")).flips.total() == 0);
  for (const CostFunction& cost : cost_functions()) CHECK(optimize_lawson(m, constant, 1, cost).flips.total() == 0);
  CHECK(m.tet == m0.tet);
}

TEST_CASE("optimize_lawson (3D): bad channel counts are refused") {
  Mesh3 m = delaunay_tetrahedralization(test::grid_points3(3, 3, 3));
  CHECK_THROWS(optimize_lawson(m, std::vector<float>(27, 0.f), 0, find_cost("variance")));
  CHECK_THROWS(optimize_lawson(m, std::vector<float>(26, 0.f), 1, find_cost("variance")));
}
