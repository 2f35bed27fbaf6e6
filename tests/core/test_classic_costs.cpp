// The classic edge costs of Dyn, Levin and Rippa (1990), generalized to
// facets: hand-computed cases, their two forms on a hand-built quad, and
// what they share (zero on a plane, the facet-form table entries).

#include "core/costs.hpp"
#include "util/error.hpp"
#include "image/optimizer.hpp"
#include "test_support.hpp"
#include "image/triangulation.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace ddt;

namespace {

// The hand-computed facet of these tests: the edge from base (0, 0) to
// (0, 1) on the y axis, apex1 = (-1, 0) left of it, apex2 = (2, 0.5) right
// of it; values 0 on the edge, 1 at apex1, 6 at apex2. Then
//   P1(x, y) = -x   (g1 = (-1, 0)),   P2(x, y) = 3x   (g2 = (3, 0)),
// and the unit normal from s1 into s2 is (1, 0).
struct HandFacet {
  double g1[2] = {-1, 0}, g2[2] = {3, 0}, normal[2] = {1, 0};
  double base[2] = {0, 0}, apex1[2] = {-1, 0}, apex2[2] = {2, 0.5};
  FacetPair pair() const {
    FacetPair f;
    f.dim = 2;
    f.g1 = g1, f.g2 = g2, f.normal = normal, f.base = base, f.apex1 = apex1, f.apex2 = apex2;
    f.z_base = 0, f.z_apex1 = 1, f.z_apex2 = 6;
    return f;
  }
};

FacetPair gradients_only(const double* g1, const double* g2, int dim) {
  FacetPair f;
  f.dim = dim;
  f.g1 = g1, f.g2 = g2;
  return f;
}

}  // namespace

TEST_CASE("abn_facet_cost: hand-computed angles between the graph normals") {
  // Normals (-g, 1): (1, 0, 1) and (-3, 0, 1); cos = (1 - 3) / (sqrt 2 sqrt 10).
  CHECK(abn_facet_cost(HandFacet().pair()) == doctest::Approx(std::acos(-2 / std::sqrt(20.0))));
  CHECK(abn_facet_cost(HandFacet().pair()) == doctest::Approx(2.0344439357957027));
  const double flat[2] = {0, 0}, slope1[2] = {1, 0}, minus1[2] = {-1, 0}, diag[2] = {1, 1}, other[2] = {1, -1};
  CHECK(abn_facet_cost(gradients_only(flat, slope1, 2)) == doctest::Approx(M_PI / 4));   // 45 degrees
  CHECK(abn_facet_cost(gradients_only(slope1, minus1, 2)) == doctest::Approx(M_PI / 2)); // (-1,0,1).(1,0,1) = 0
  CHECK(abn_facet_cost(gradients_only(diag, diag, 2)) == 0.0);
  // (-1,-1,1).(-1,1,1) = 1, both of length sqrt 3: cos = 1/3.
  CHECK(abn_facet_cost(gradients_only(diag, other, 2)) == doctest::Approx(std::acos(1.0 / 3)));
  // 3D: (0,0,0,1) against (0,0,-sqrt 3,1) / 2: 60 degrees.
  const double zero3[3] = {0, 0, 0}, up3[3] = {0, 0, std::sqrt(3.0)};
  CHECK(abn_facet_cost(gradients_only(zero3, up3, 3)) == doctest::Approx(M_PI / 3));
  // Tiny angles keep their precision (atan2, not acos of a rounded cosine).
  const double tiny[2] = {1e-9, 0};
  CHECK(abn_facet_cost(gradients_only(flat, tiny, 2)) == doctest::Approx(1e-9).epsilon(1e-6));
}

TEST_CASE("jnd_facet_cost: hand-computed jump of the normal derivative") {
  CHECK(jnd_facet_cost(HandFacet().pair()) == doctest::Approx(4.0));  // |1 * (-1 - 3)|
  // An edge along the diagonal: normal (1, -1) / sqrt 2; g1 - g2 = (2, -2) is parallel to it.
  const double g1[2] = {2, -1}, g2[2] = {0, 1}, n[2] = {M_SQRT1_2, -M_SQRT1_2};
  FacetPair f = gradients_only(g1, g2, 2);
  f.normal = n;
  CHECK(jnd_facet_cost(f) == doctest::Approx(2 * std::sqrt(2.0)));
  CHECK(find_cost("jnd").facet_geometry);
}

TEST_CASE("dlp_facet_cost and dp_facet_cost: hand-computed deviations from the planes") {
  // d1 = P1(apex2) - 6 = -2 - 6 = -8, d2 = P2(apex1) - 1 = -3 - 1 = -4.
  CHECK(dlp_facet_cost(HandFacet().pair()) == doctest::Approx(std::sqrt(80.0)));
  // Perpendicular: 8 / sqrt(1 + 1) and 4 / sqrt(1 + 9).
  CHECK(dp_facet_cost(HandFacet().pair()) == doctest::Approx(std::sqrt(32.0 + 1.6)));
  // DLP = JND * (distances of the apexes from the edge): 4 * sqrt(2^2 + 1^2).
  CHECK(dlp_facet_cost(HandFacet().pair()) ==
        doctest::Approx(jnd_facet_cost(HandFacet().pair()) * std::sqrt(5.0)));
  CHECK(find_cost("dlp").facet_geometry);
  CHECK(find_cost("dp").facet_geometry);
}

TEST_CASE("classic costs: both forms on a hand-built quad") {
  // The hand facet as a mesh: s1 = (0, 1, 2) of area 1/2, s2 = (0, 1, 3) of area 1.
  const std::vector<Point2> points = {{0, 0}, {0, 1}, {-1, 0}, {2, 0.5}};
  const Mesh2 m = test::mesh_from_triangles(points, {{0, 1, 2}, {0, 1, 3}});
  REQUIRE(check_mesh(m).empty());
  const std::vector<float> values = {0, 0, 1, 6};
  const HandFacet hand;  // owns the coordinates f points at
  const FacetPair f = hand.pair();
  struct Case {
    const char* name;
    double edge_cost;
  };
  const Case cases[] = {{"abn", abn_facet_cost(f)},
                        {"jnd", 4.0},
                        {"dlp", std::sqrt(80.0)},
                        {"dp", std::sqrt(33.6)},
                        {"sederberg", 6.0}};  // |g1||g2| - g1.g2 = 3 + 3
  for (const Case& c : cases) {
    const std::string name = c.name;
    CAPTURE(name);
    // Edge sum: the one interior edge. Weighted content: c * (1/2 + 1) / 3.
    CHECK(total_cost(m, values, 1, find_cost(std::string(c.name) + "-edge")) == doctest::Approx(c.edge_cost));
    CHECK(total_cost(m, values, 1, find_cost(c.name)) == doctest::Approx(c.edge_cost * 1.5 / 3));
  }
}

TEST_CASE("classic costs: zero on a plane, positive across a crease, in every channel") {
  // Coordinates on a 1/1024 grid, so the planes' values are exact floats.
  std::vector<Point2> points = test::random_points(120, 5);
  for (Point2& p : points) p = {std::round(p.x * 1024) / 1024, std::round(p.y * 1024) / 1024};
  const Mesh2 m = delaunay_triangulation(points);
  std::vector<float> plane, crease;
  for (const Point2& p : m.points) {
    plane.push_back(static_cast<float>(0.25 * p.x - 0.5 * p.y + 1));  // channel 0
    plane.push_back(static_cast<float>(-0.125 * p.x + 2));            // channel 1
    crease.push_back(static_cast<float>(0.3 * std::abs(p.x - 5)));
    crease.push_back(0.0f);
  }
  for (const CostFunction& cost : cost_functions()) {
    if (cost.form == CostForm::simplex_weight) continue;
    const std::string name = cost.name;
    CAPTURE(name);
    CHECK(total_cost(m, plane, 2, cost) < 1e-9);
    CHECK(total_cost(m, crease, 2, cost) > 0.1);
  }
}

TEST_CASE("classic costs: table entries, forms, and the error for an unknown name") {
  for (const char* name : {"abn", "jnd", "dlp", "dp"}) {
    CAPTURE(name);
    CHECK(find_cost(name).form == CostForm::facet_weighted_content);
    CHECK(find_cost(std::string(name) + "-edge").form == CostForm::facet_sum);
    CHECK((find_cost(name).facet_cost == find_cost(std::string(name) + "-edge").facet_cost));
  }
  try {
    find_cost("abm");
    FAIL("no error for an unknown cost");
  } catch (const Error& e) {
    const std::string msg = e.what();
    CHECK(msg.find("'abm'") != std::string::npos);
    for (const char* name : {"sederberg", "sederberg-edge", "abn", "abn-edge", "jnd", "jnd-edge", "dlp", "dlp-edge"})
      CHECK(msg.find(name) != std::string::npos);
  }
}
