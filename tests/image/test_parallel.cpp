// The fast paths of issue 4 against the plain ones: the blocked grid
// triangulation, the optimizer's regions and specialized evaluators.

#include "image/optimizer.hpp"
#include "test_support.hpp"
#include "image/triangulation.hpp"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <random>
#include <tuple>

using namespace ddt;

namespace {

using test::random_values;

// Values like an 8-bit photograph: smooth, with flat patches and steps.
std::vector<float> image_values(int w, int h, int K, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-2, 2);
  std::vector<float> v;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < K; ++k) {
        int level = (x + 2 * y) % 37 < 18 ? 60 : 190;
        level += static_cast<int>(40 * std::sin(0.13 * x + 0.07 * k) * std::cos(0.11 * y));
        if ((x / 9 + y / 7) % 5 == 0) level = 128;  // flat patches
        else level += noise(rng);
        v.push_back(static_cast<float>(std::clamp(level, 0, 255)) / 255.0f);
      }
  return v;
}

bool sorted_canonically(const Mesh2& m) {
  for (index_t t = 0; t < m.triangle_count(); ++t) {
    const index_t* v = &m.tri[3 * t];
    if (v[0] > v[1] || v[0] > v[2]) return false;
    if (t > 0) {
      const index_t* u = &m.tri[3 * (t - 1)];
      if (std::array<index_t, 3>{u[0], u[1], u[2]} > std::array<index_t, 3>{v[0], v[1], v[2]}) return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("delaunay_triangulation: a grid cut into blocks equals the general construction") {
  // Grids larger than a block (16 cells) in one or both directions, offset.
  for (auto [w, h, x0, y0] : {std::tuple{50, 37, 0.5, 0.5}, std::tuple{70, 18, 100.5, 7.5}, std::tuple{17, 90, 3.0, -4.0},
                              std::tuple{2, 40, 0.5, 0.5}, std::tuple{33, 2, 0.5, 0.5}}) {
    CAPTURE(w);
    CAPTURE(h);
    std::vector<Point2> grid;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) grid.push_back({x0 + x, y0 + y});
    const Mesh2 blocked = delaunay_triangulation(grid);
    REQUIRE(check_mesh(blocked).empty());
    CHECK(blocked.triangle_count() == 2 * (w - 1) * (h - 1));
    CHECK(sorted_canonically(blocked));
    CHECK(is_delaunay(blocked));
    for (index_t e = 0; e < blocked.half_edge_count(); ++e) CHECK_FALSE(violates_perturbed_delaunay(blocked, e));
    // The same points column by column are not a row-major grid: CGAL's
    // general path. The smallest id of every cell is still its top-left
    // corner, so the tie-break picks the same diagonals: the same triangles
    // once the ids are mapped back.
    std::vector<Point2> by_column;
    for (int x = 0; x < w; ++x)
      for (int y = 0; y < h; ++y) by_column.push_back({x0 + x, y0 + y});
    Mesh2 general = delaunay_triangulation(by_column);
    REQUIRE(check_mesh(general).empty());
    for (index_t& v : general.tri) v = (v % h) * w + v / h;
    general.points = grid;
    CHECK(test::triangle_set(general) == test::triangle_set(blocked));
  }
}

TEST_CASE("optimize_lawson: the fast evaluators decide exactly as flip_costs") {
  const int w = 40, h = 31;
  for (const char* name : {"sederberg", "sederberg-edge", "variance"})
    for (int K : {1, 3, 2})
      for (long long regions : {-1LL, 200LL}) {
        CAPTURE(name);
        CAPTURE(K);
        CAPTURE(regions);
        const std::vector<float> values = image_values(w, h, K, 5);
        Mesh2 fast = delaunay_triangulation(test::grid_points(w, h));
        Mesh2 reference = fast;
        const double total_before = total_cost(fast, values, K, find_cost(name));
        LawsonOptions opt;
        opt.region_triangles = regions;
        const LawsonStats a = optimize_lawson(fast, values, K, find_cost(name), opt);
        opt.fast_evaluation = false;
        const LawsonStats b = optimize_lawson(reference, values, K, find_cost(name), opt);
        CHECK(a.flips > 0);
        CHECK(a.flips == b.flips);
        CHECK(a.tests == b.tests);
        CHECK(a.iterations == b.iterations);
        CHECK(fast.tri == reference.tri);
        CHECK(fast.opp == reference.opp);
        CHECK(a.cost_after == doctest::Approx(b.cost_after).epsilon(1e-12));
        // The fast Sederberg path sums the total before from its regions'
        // caches and tracks the total after from the gains.
        CHECK(a.cost_before == doctest::Approx(total_before).epsilon(1e-12));
        CHECK(a.cost_after == doctest::Approx(total_cost(fast, values, K, find_cost(name))).epsilon(1e-12));
        LawsonOptions none = opt;  // no iteration: the totals are still the mesh's
        none.fast_evaluation = true;
        none.max_iterations = 0;
        Mesh2 untouched = delaunay_triangulation(test::grid_points(w, h));
        const LawsonStats c = optimize_lawson(untouched, values, K, find_cost(name), none);
        CHECK(c.flips == 0);
        CHECK(c.cost_before == doctest::Approx(total_before).epsilon(1e-12));
        CHECK(c.cost_after == c.cost_before);
        CHECK(b.skipped_flat == 0);
        CHECK(a.skipped_flat > 0);  // the flat patches
      }
}

TEST_CASE("optimize_lawson: regions give the same mesh on any number of threads, locally optimal") {
  const int w = 90, h = 70;
  const std::vector<float> values = image_values(w, h, 3, 11);
  const Mesh2 start = delaunay_triangulation(test::grid_points(w, h));
  for (const char* name : {"sederberg", "variance", "abn"}) {
    CAPTURE(name);
    const CostFunction& cost = find_cost(name);
    LawsonOptions opt;
    opt.region_triangles = 2 * (w - 1) * 6;  // bands of 6 rows: many seams
    opt.region_origin = 2 * (w - 1) * 3;
    std::vector<Mesh2> results;
    std::vector<LawsonStats> stats;
    for (int threads : {1, 2, 4}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      Mesh2 m = start;
      stats.push_back(optimize_lawson(m, values, 3, cost, opt));
      results.push_back(std::move(m));
    }
    CHECK(stats[0].regions > 10);
    CHECK(stats[0].iterations >= 2);  // phases
    for (std::size_t i = 1; i < results.size(); ++i) {
      CHECK(results[i].tri == results[0].tri);
      CHECK(stats[i].flips == stats[0].flips);
      CHECK(stats[i].cost_after == stats[0].cost_after);
    }
    const Mesh2& m = results[0];
    CHECK(check_mesh(m).empty());
    CHECK(stats[0].cost_after < stats[0].cost_before);
    int not_optimal = 0;
    for (index_t e = 0; e < m.half_edge_count(); ++e) {
      if (!is_flippable(m, e)) continue;
      const FlipCosts fc = flip_costs(m, values, 3, cost, e);
      if (fc.improves(opt.relative_tolerance)) ++not_optimal;
    }
    CHECK(not_optimal == 0);
    // The sequential order reaches another local optimum. Seam edges wait
    // for the next phase, which costs a little: here, with bands of 6 rows,
    // a few percent (with the default bands of 128 rows, about 0.05%;
    // docs/performance.md).
    Mesh2 sequential = start;
    LawsonOptions one;
    one.region_triangles = -1;
    const LawsonStats s = optimize_lawson(sequential, values, 3, cost, one);
    CHECK(stats[0].cost_after == doctest::Approx(s.cost_after).epsilon(0.1));
  }
}

TEST_CASE("total_cost: the same total on any number of threads") {
  Mesh2 m = delaunay_triangulation(test::random_points(3000, 4, 50.0));
  const std::vector<float> values = random_values(m.points.size(), 3, 2);
  for (const CostFunction& cost : cost_functions()) {
    CAPTURE(cost.name);
    double one = 0, two = 0;
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
      one = total_cost(m, values, 3, cost);
    }
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
      two = total_cost(m, values, 3, cost);
    }
    CHECK(one == two);
  }
}
