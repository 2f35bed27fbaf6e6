#include "image/annealing.hpp"
#include "util/error.hpp"
#include "test_support.hpp"
#include "image/triangulation.hpp"
#include "pipeline/upscale.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace ddt;

namespace {

using test::random_values;

AnnealOptions quick(std::uint64_t seed) {
  AnnealOptions o;
  o.seed = seed;
  o.temperature_steps = 12;
  o.cooling = 0.7;
  return o;
}

}  // namespace

TEST_CASE("optimize_anneal: the same seed gives the same mesh, another seed another") {
  const Mesh2 start = delaunay_triangulation(test::random_points(200, 31));
  const std::vector<float> values = random_values(start.points.size(), 1, 32);
  const CostFunction& cost = find_cost("sederberg");
  Mesh2 a = start, b = start, c = start;
  const AnnealStats sa = optimize_anneal(a, values, 1, cost, quick(7));
  const AnnealStats sb = optimize_anneal(b, values, 1, cost, quick(7));
  optimize_anneal(c, values, 1, cost, quick(8));
  CHECK(a.tri == b.tri);
  CHECK(a.opp == b.opp);
  CHECK(sa.accepted == sb.accepted);
  CHECK(sa.cost_after == sb.cost_after);
  CHECK(test::triangle_set(a) != test::triangle_set(c));
}

TEST_CASE("optimize_anneal: ends valid and locally optimal, for every cost") {
  for (const CostFunction& cost : cost_functions()) {
    const std::string name = cost.name;
    CAPTURE(name);
    Mesh2 m = delaunay_triangulation(test::random_points(150, 41));
    const double area = total_area(m);
    const std::vector<float> values = random_values(m.points.size(), 2, 42);
    double last_running = 0;
    AnnealOptions opt = quick(3);
    opt.on_step = [&](int, double, long long, double total) { last_running = total; };
    LawsonOptions lawson;
    const AnnealStats st = optimize_anneal(m, values, 2, cost, opt, lawson);
    CHECK(st.temperature_steps == 12);
    CHECK(st.accepted > 0);
    CHECK(st.uphill > 0);
    CHECK(st.initial_temperature > 0);
    CHECK(st.final_temperature == doctest::Approx(st.initial_temperature * std::pow(0.7, 11)));
    // The running total (sum of local changes) agrees with a recount.
    CHECK(last_running == doctest::Approx(st.cost_annealed).epsilon(1e-9));
    CHECK(st.cost_after <= st.cost_annealed);
    CHECK(st.cost_after == doctest::Approx(total_cost(m, values, 2, cost)).epsilon(1e-12));
    CHECK(check_mesh(m).empty());
    CHECK(total_area(m) == doctest::Approx(area).epsilon(1e-12));
    for (index_t e = 0; e < m.half_edge_count(); ++e) {
      if (!is_flippable(m, e)) continue;
      const FlipCosts fc = flip_costs(m, values, 2, cost, e);
      CHECK_FALSE(fc.improves(lawson.relative_tolerance));
    }
  }
}

TEST_CASE("optimize_anneal: at a vanishing temperature it only descends") {
  Mesh2 m = delaunay_triangulation(test::random_points(150, 51));
  const std::vector<float> values = random_values(m.points.size(), 1, 52);
  AnnealOptions opt = quick(5);
  opt.initial_temperature = 1e-300;
  opt.final_lawson = false;
  double previous = total_cost(m, values, 1, find_cost("variance"));
  opt.on_step = [&](int, double, long long, double total) {
    CHECK(total <= previous + 1e-12);
    previous = total;
  };
  const AnnealStats st = optimize_anneal(m, values, 1, find_cost("variance"), opt);
  CHECK(st.uphill == 0);
  CHECK(st.accepted > 0);
  CHECK(st.cost_annealed < st.cost_before);
  CHECK(st.lawson.flips == 0);
}

TEST_CASE("optimize_anneal: a hot start accepts flips that raise the cost") {
  Mesh2 m = delaunay_triangulation(test::random_points(150, 61));
  const std::vector<float> values = random_values(m.points.size(), 1, 62);
  AnnealOptions opt = quick(9);
  opt.initial_acceptance = 0.99;
  opt.temperature_steps = 1;
  opt.final_lawson = false;
  const AnnealStats st = optimize_anneal(m, values, 1, find_cost("sederberg"), opt);
  CHECK(st.uphill > st.accepted / 4);
  CHECK(st.cost_annealed > st.cost_before);
  long long interior = 0;
  for (index_t h = 0; h < m.half_edge_count(); ++h) interior += m.opp[h] != no_edge;
  CHECK(st.proposals == interior / 2);  // one step of one proposal per interior edge
  CHECK(st.flippable <= st.proposals);
}

TEST_CASE("optimize_anneal: on constant data every flip is neutral, so annealing wanders where Lawson does not") {
  // The paper's observation in its purest form: where the data are flat,
  // Metropolis accepts every flip (delta = 0), so annealing leaves long thin
  // triangles that the cost cannot tell from the Delaunay ones.
  const Mesh2 start = delaunay_triangulation(test::grid_points(12, 10));
  const std::vector<float> values(start.points.size(), 0.5f);
  for (const char* name : {"sederberg", "variance", "abn", "jnd"}) {
    CAPTURE(name);
    Mesh2 lawson = start, anneal = start;
    CHECK(optimize_lawson(lawson, values, 1, find_cost(name)).flips == 0);
    const AnnealStats st = optimize_anneal(anneal, values, 1, find_cost(name), quick(1));
    CHECK(st.initial_temperature == 0);  // no uphill flip to scale T0 by
    CHECK(st.accepted > 0);
    CHECK(st.lawson.flips == 0);
    CHECK(test::triangle_set(anneal) != test::triangle_set(start));
  }
}

TEST_CASE("initial_temperature: accepts the mean uphill flip with the given probability") {
  // One interior edge: its flip is the only move, uphill by delta.
  const std::vector<Point2> points = {{0, 0}, {0, 1}, {-1, 0}, {2, 0.5}};
  Mesh2 m = test::mesh_from_triangles(points, {{0, 1, 2}, {0, 1, 3}});
  const std::vector<float> values = {0, 0, 1, 6};
  const CostFunction& cost = find_cost("sederberg");
  index_t e = 0;
  while (m.opp[e] == no_edge) ++e;
  REQUIRE(is_flippable(m, e));
  double delta = -flip_costs(m, values, 1, cost, e).gain();
  if (delta < 0) {
    flip_edge(m, e);
    delta = -delta;
  }
  REQUIRE(delta > 0);
  CHECK(initial_temperature(m, values, 1, cost, 0.5, 1) == doctest::Approx(delta / std::log(2.0)));
  CHECK(initial_temperature(m, values, 1, cost, 0.8, 1) == doctest::Approx(delta / -std::log(0.8)));
}

TEST_CASE("optimize_anneal and upscale: bad options are clear errors") {
  Mesh2 m = delaunay_triangulation(test::random_points(20, 71));
  const std::vector<float> values = random_values(m.points.size(), 1, 72);
  AnnealOptions bad;
  bad.cooling = 1.5;
  CHECK_THROWS_AS(optimize_anneal(m, values, 1, find_cost("sederberg"), bad), Error);
  bad = {};
  bad.initial_acceptance = 1;
  CHECK_THROWS_AS(optimize_anneal(m, values, 1, find_cost("sederberg"), bad), Error);
  CHECK_THROWS_AS(optimize_anneal(m, values, 0, find_cost("sederberg")), Error);
  try {
    optimizer_by_name("annealing");
    FAIL("no error for an unknown optimizer");
  } catch (const Error& e) {
    const std::string msg = e.what();
    CHECK(msg.find("'annealing'") != std::string::npos);
    CHECK(msg.find("lawson") != std::string::npos);
    CHECK(msg.find("lawson, anneal, lookahead") != std::string::npos);
  }
}

TEST_CASE("upscale: --optimizer anneal is reproducible with its seed") {
  const Image img = test::sampled_image(16, 12, 3, [](double x, double y, int c) {
    return 0.5 + 0.4 * std::sin(0.7 * x + 0.3 * c) * std::cos(0.5 * y);
  });
  UpscaleOptions options;
  options.optimizer = Optimizer::anneal;
  options.anneal = quick(11);
  UpscaleStats s1, s2, s3;
  const Image a = upscale(img, 48, 36, options, &s1);
  const Image b = upscale(img, 48, 36, options, &s2);
  options.anneal.seed = 12;
  const Image c = upscale(img, 48, 36, options, &s3);
  CHECK(a.pixels == b.pixels);
  CHECK(a.pixels != c.pixels);
  CHECK(s1.flips == s2.flips);
  CHECK(s1.flips > 0);
}
