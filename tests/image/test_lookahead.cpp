#include "image/lookahead.hpp"
#include "test_support.hpp"
#include "image/triangulation.hpp"
#include "pipeline/upscale.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace ddt;

namespace {

using test::random_values;

}  // namespace

TEST_CASE("optimize_lookahead: below Lawson, valid, and optimal for single flips and the pairs, for every cost") {
  long long pairs = 0;
  for (const CostFunction& cost : cost_functions()) {
    const std::string name = cost.name;
    CAPTURE(name);
    Mesh2 m = delaunay_triangulation(test::random_points(200, 81));
    const double area = total_area(m);
    const std::vector<float> values = random_values(m.points.size(), 2, 82);
    LawsonOptions lawson;
    const LookaheadStats st = optimize_lookahead(m, values, 2, cost, lawson);
    pairs += st.pairs;
    CHECK(st.cost_after <= st.first_lawson.cost_after);
    if (st.pairs > 0) CHECK(st.cost_after < st.first_lawson.cost_after);
    CHECK(st.cost_after == doctest::Approx(total_cost(m, values, 2, cost)).epsilon(1e-12));
    CHECK(check_mesh(m).empty());
    CHECK(total_area(m) == doctest::Approx(area).epsilon(1e-12));
    for (index_t e = 0; e < m.half_edge_count(); ++e) {
      if (m.opp[e] < e || !is_flippable(m, e)) continue;
      const FlipCosts first = flip_costs(m, values, 2, cost, e);
      CHECK_FALSE(first.improves(lawson.relative_tolerance));
      const index_t f = m.opp[e];
      flip_edge(m, e);
      for (index_t h : {next_edge(e), prev_edge(e), next_edge(f), prev_edge(f)}) {
        if (!is_flippable(m, h)) continue;
        const FlipCosts second = flip_costs(m, values, 2, cost, h);
        CHECK(first.gain() + second.gain() <=
              lawson.relative_tolerance * std::max(first.before + second.before, first.noise_scale + second.noise_scale) +
                  1e-15);
      }
      flip_edge(m, e);
    }
  }
  CHECK(pairs > 0);  // the move does something on random data
}

TEST_CASE("upscale: --optimizer lookahead lowers the cost below Lawson's") {
  const Image img = test::sampled_image(20, 16, 1, [](double x, double y, int) {
    return 0.5 + 0.4 * std::sin(0.9 * x + 0.4 * y) * std::cos(0.6 * y - 0.2 * x);
  });
  UpscaleOptions options;
  UpscaleStats lawson, lookahead;
  upscale(img, 40, 32, options, &lawson);
  options.optimizer = Optimizer::lookahead;
  upscale(img, 40, 32, options, &lookahead);
  CHECK(lookahead.cost_before == lawson.cost_before);
  CHECK(lookahead.cost_after <= lawson.cost_after);
  CHECK(lookahead.flips >= lawson.flips);
}
