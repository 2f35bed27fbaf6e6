// Tests of the dimension-generic optimizer: local costs against the total,
// the Lawson procedure's guarantees, and the region schedule's independence
// of the thread count.

#include "core/check_mesh.hpp"
#include "core/delaunay.hpp"
#include "core/lawson.hpp"
#include "core_test_support.hpp"
#include "../test_support.hpp"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <set>
#include <cmath>

using namespace ddt;
using namespace ddt::core;
using namespace ddt::core::test;

namespace {

// A blurred ball of radius r in the middle of the points' box: a surface
// the costs want to follow.
template <int D>
std::vector<float> ball_values(const std::vector<Vec<D>>& points, double r) {
  Vec<D> centre{};
  for (const Vec<D>& p : points)
    for (int k = 0; k < D; ++k) centre[k] = std::max(centre[k], p[k] / 2 + 0.05);
  std::vector<float> v;
  for (const Vec<D>& p : points) {
    double d2 = 0;
    for (int k = 0; k < D; ++k) d2 += (p[k] - centre[k]) * (p[k] - centre[k]);
    v.push_back(static_cast<float>(0.5 + 0.5 * std::tanh(3 * (r - std::sqrt(d2)))));
  }
  return v;
}

// Every flip propose_flip offers on the mesh (up to `wanted`), over every
// simplex with 2 .. D vertices of every cell.
template <int D>
std::vector<FlipPlan<D>> some_flips(const SimplexMesh<D>& mesh, std::size_t wanted) {
  std::vector<FlipPlan<D>> out;
  for (index_t c = 0; c < mesh.slot_count() && out.size() < wanted; ++c) {
    if (!mesh.is_live(c)) continue;
    for (unsigned mask = 0; mask < (1u << (D + 1)); ++mask) {
      const int bits = std::popcount(mask);
      if (bits < 2 || bits > D) continue;
      FlipPlan<D> plans[2];
      const int n = propose_flip<D>(mesh, c, mask, plans, 2);
      for (int p = 0; p < n; ++p) out.push_back(plans[p]);
    }
  }
  return out;
}

}  // namespace

TEST_CASE_TEMPLATE("core flip_costs: the local gain equals the change of the total, for every cost and flip kind", T,
                   Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  for (const CostFunction& cost : cost_functions()) {
    const std::string name = cost.name;
    CAPTURE(name);
    for (const bool grid : {false, true}) {
      CAPTURE(grid);
      const SimplexMesh<D> m0 = grid ? delaunay<D>(grid_points<D>(D == 4 ? 3 : 4)) : delaunay<D>(random_points<D>(40, 5));
      const std::vector<float> values = ddt::test::random_values(m0.points.size(), 2, 6);
      const std::vector<FlipPlan<D>> flips = some_flips(m0, 300);
      REQUIRE(!flips.empty());
      const double before = total_cost<D>(m0, values.data(), 2, cost);
      for (std::size_t i = 0; i < flips.size(); i += 7) {
        SimplexMesh<D> m = m0;
        const LocalCosts fc = flip_costs<D>(m, values.data(), 2, cost, flips[i]);
        apply_flip<D>(m, flips[i]);
        const double after = total_cost<D>(m, values.data(), 2, cost);
        CHECK(before - after == doctest::Approx(fc.gain()).epsilon(1e-9).scale(std::abs(before)));
      }
    }
  }
}

TEST_CASE_TEMPLATE("core optimize_lawson: the cost never rises - the mesh ends valid, locally optimal, same content", T,
                   Dim<2>, Dim<3>) {
  constexpr int D = T::value;
  for (const CostFunction& cost : cost_functions()) {
    const std::string name = cost.name;
    CAPTURE(name);
    SimplexMesh<D> m = delaunay<D>(grid_points<D>(D == 2 ? 14 : 7));
    const double content = total_content(m);
    const std::vector<float> values = ball_values<D>(m.points, D == 2 ? 4.2 : 2.1);
    std::vector<double> totals;
    LawsonOptions options;
    options.on_iteration = [&](int, const FlipCounts&, double total) { totals.push_back(total); };
    const LawsonStats st = optimize_lawson<D>(m, values, 1, cost, options);
    CHECK(st.flips.total() > 0);
    CHECK(st.cost_after < st.cost_before);
    double previous = st.cost_before;
    for (double t : totals) {
      CHECK(t <= previous);
      previous = t;
    }
    CHECK(totals.back() == doctest::Approx(st.cost_after).epsilon(1e-9));
    CHECK(check_mesh(m) == "");
    CHECK(total_content(m) == doctest::Approx(content).epsilon(1e-12));
    for (const FlipPlan<D>& plan : some_flips(m, 1 << 30))
      CHECK_FALSE(flip_costs<D>(m, values.data(), 1, cost, plan).improves(options.relative_tolerance));
  }
}

TEST_CASE_TEMPLATE("core optimize_lawson: a linear field makes no sederberg flips - a constant field none at all", T,
                   Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  SimplexMesh<D> m = delaunay<D>(grid_points<D>(D == 4 ? 3 : 5));
  const SimplexMesh<D> m0 = m;
  std::vector<float> linear, constant(m.points.size(), 0.25f);
  for (const Vec<D>& p : m.points) {
    double z = 0.1;
    for (int k = 0; k < D; ++k) z += (k % 2 ? -0.05 : 0.1) * (k + 1) * p[k];
    linear.push_back(static_cast<float>(z));
  }
  CHECK(optimize_lawson<D>(m, linear, 1, find_cost("sederberg")).flips.total() == 0);
  for (const CostFunction& cost : cost_functions()) CHECK(optimize_lawson<D>(m, constant, 1, cost).flips.total() == 0);
  CHECK(m.cell == m0.cell);
}

TEST_CASE("core optimize_lawson: bad channel counts and value arrays are refused") {
  SimplexMesh<3> m = delaunay<3>(grid_points<3>(3));
  CHECK_THROWS(optimize_lawson<3>(m, std::vector<float>(27, 0.f), 0, find_cost("variance")));
  CHECK_THROWS(optimize_lawson<3>(m, std::vector<float>(26, 0.f), 1, find_cost("variance")));
  CHECK_THROWS(optimize_lawson<3>(m, std::vector<float>(27 * 9, 0.f), 9, find_cost("variance")));
}

TEST_CASE_TEMPLATE("core optimize_lawson: the region schedule gives the same mesh for 1 and 2 threads, valid and "
                   "locally optimal",
                   T, Dim<2>, Dim<3>) {
  constexpr int D = T::value;
  const int n = D == 2 ? 40 : 12;
  const SimplexMesh<D> m0 = delaunay<D>(grid_points<D>(n));
  const std::vector<float> values = ball_values<D>(m0.points, n / 3.0);
  for (const char* name : {"variance", "sederberg"}) {
    CAPTURE(name);
    const CostFunction& cost = find_cost(name);
    LawsonOptions options;
    options.region_vertices = D == 2 ? n * 8 : n * n * 3;  // thin bands: many seams
    SimplexMesh<D> one = m0, two = m0;
    LawsonStats st1, st2;
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
      st1 = optimize_lawson<D>(one, values, 1, cost, options);
    }
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
      st2 = optimize_lawson<D>(two, values, 1, cost, options);
    }
    CHECK(st1.regions > 2);
    CHECK(st1.deferred > 0);
    CHECK(one.cell == two.cell);
    CHECK(one.opp == two.opp);
    CHECK(one.free_slots == two.free_slots);
    CHECK(st1.cost_after == st2.cost_after);
    CHECK(st1.flips.by_kind == st2.flips.by_kind);
    CHECK(check_mesh(one) == "");
    for (const FlipPlan<D>& plan : some_flips(one, 1 << 30))
      CHECK_FALSE(flip_costs<D>(one, values.data(), 1, cost, plan).improves(options.relative_tolerance));
    // Another local optimum than the sequential order's, near it (these
    // bands are far thinner than real ones, so seams are everywhere).
    SimplexMesh<D> sequential = m0;
    LawsonOptions single;
    single.region_vertices = -1;
    const LawsonStats st0 = optimize_lawson<D>(sequential, values, 1, cost, single);
    CHECK(st0.regions == 1);
    CHECK(st0.deferred == 0);
    CHECK(st1.cost_after < st1.cost_before);
    CHECK(st1.cost_after == doctest::Approx(st0.cost_after).epsilon(0.2));
  }
}

TEST_CASE_TEMPLATE("core optimize_lawson: no flip removes a simplex the caller keeps - keeping none changes nothing", T,
                   Dim<2>, Dim<3>) {
  constexpr int D = T::value;
  const SimplexMesh<D> start = delaunay<D>(grid_points<D>(D == 2 ? 14 : 7));
  const std::vector<float> values = ball_values<D>(start.points, D == 2 ? 4.2 : 2.1);
  const CostFunction& cost = find_cost("variance");
  SimplexMesh<D> free_mesh = start;
  const LawsonStats free_run = optimize_lawson<D>(free_mesh, values, 1, cost);
  REQUIRE(free_run.flips.total() > 0);

  // A rule that keeps nothing is the unrestricted procedure, flip for flip.
  SimplexMesh<D> none = start;
  LawsonOptions keep_none;
  keep_none.kept_simplex = [](const index_t*, int) { return false; };
  CHECK(optimize_lawson<D>(none, values, 1, cost, keep_none).flips.total() == free_run.flips.total());
  CHECK(none.cell == free_mesh.cell);

  // Every edge kept: the flips that remove an edge (2D's 2-2, 3D's 3-2,
  // 4-4 and hull 2-2) never happen, and every edge of the start survives.
  SimplexMesh<D> kept = start;
  LawsonOptions keep_edges;
  std::atomic<long long> asked{0};
  keep_edges.kept_simplex = [&](const index_t*, int count) {
    ++asked;
    return count == 2;
  };
  const LawsonStats st = optimize_lawson<D>(kept, values, 1, cost, keep_edges);
  CHECK(asked > 0);
  CHECK(check_mesh(kept) == "");
  auto edges_of = [](const SimplexMesh<D>& m) {
    std::set<std::pair<index_t, index_t>> edges;
    for (index_t c = 0; c < m.slot_count(); ++c) {
      if (!m.is_live(c)) continue;
      const auto v = m.cell_vertices(c);
      for (int i = 0; i <= D; ++i)
        for (int j = i + 1; j <= D; ++j) edges.insert(std::minmax(v[i], v[j]));
    }
    return edges;
  };
  const auto before = edges_of(start), after = edges_of(kept);
  CHECK(std::includes(after.begin(), after.end(), before.begin(), before.end()));
  if constexpr (D == 2) CHECK(st.flips.total() == 0);
  if constexpr (D == 3) {
    CHECK(st.flips.count(3, 2) == 0);
    CHECK(st.flips.count(4, 4) == 0);
    CHECK(st.flips.count(2, 2) == 0);
  }
}
