#include "core/costs.hpp"
#include "util/error.hpp"

#include <doctest/doctest.h>

using namespace ddt;

TEST_CASE("sederberg_cost: hand-computed gradient pairs") {
  const double x[2] = {1, 0}, y[2] = {0, 1}, minus_x[2] = {-1, 0}, two_x[2] = {2, 0};
  CHECK(sederberg_cost(x, y, 2) == doctest::Approx(1.0));         // 1*1 - 0
  CHECK(sederberg_cost(x, minus_x, 2) == doctest::Approx(2.0));   // 1*1 + 1
  CHECK(sederberg_cost(x, two_x, 2) == doctest::Approx(0.0));     // parallel, same way
  const double g3a[3] = {1, 2, 2}, g3b[3] = {0, 0, 3};            // |a| = 3, |b| = 3, a.b = 6
  CHECK(sederberg_cost(g3a, g3b, 3) == doctest::Approx(3.0));
}

TEST_CASE("variance_weight: population variance") {
  const double z[3] = {1, 2, 3};
  CHECK(variance_weight(z, 3) == doctest::Approx(2.0 / 3.0));
  const double flat[4] = {5, 5, 5, 5};
  CHECK(variance_weight(flat, 4) == 0.0);
}

TEST_CASE("simplex_gradient: planes in 2D and 3D are recovered") {
  using V2 = Eigen::Vector2d;
  std::array<V2, 3> p = {V2(0.5, 0.5), V2(3, 1), V2(1, 2.5)};
  auto plane = [](const V2& q) { return 2 * q.x() - 3 * q.y() + 1; };
  auto g = simplex_gradient<2>(p, {plane(p[0]), plane(p[1]), plane(p[2])});
  CHECK(g.x() == doctest::Approx(2.0));
  CHECK(g.y() == doctest::Approx(-3.0));
  using V3 = Eigen::Vector3d;
  std::array<V3, 4> q = {V3(0, 0, 0), V3(1, 0, 0), V3(0, 2, 0), V3(0.3, 0.2, 1)};
  auto f3 = [](const V3& r) { return 0.5 * r.x() + r.y() - 4 * r.z() + 7; };
  auto g3 = simplex_gradient<3>(q, {f3(q[0]), f3(q[1]), f3(q[2]), f3(q[3])});
  CHECK(g3.x() == doctest::Approx(0.5));
  CHECK(g3.y() == doctest::Approx(1.0));
  CHECK(g3.z() == doctest::Approx(-4.0));
}

TEST_CASE("simplex_content: triangle area and tetrahedron volume") {
  using V2 = Eigen::Vector2d;
  using V3 = Eigen::Vector3d;
  CHECK(simplex_content<2>({V2(0, 0), V2(1, 0), V2(0, 1)}) == doctest::Approx(0.5));
  CHECK(simplex_content<3>({V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(0, 0, 1)}) == doctest::Approx(1.0 / 6.0));
}

TEST_CASE("find_cost: known names and a clear error for unknown ones") {
  CHECK(find_cost("sederberg").form == CostForm::facet_weighted_content);
  CHECK(find_cost("variance").form == CostForm::simplex_weight);
  CHECK(find_cost("sederberg-edge").form == CostForm::facet_sum);
  try {
    find_cost("sederburg");
    FAIL("no error for an unknown cost");
  } catch (const Error& e) {
    const std::string msg = e.what();
    CHECK(msg.find("sederburg") != std::string::npos);
    CHECK(msg.find("variance") != std::string::npos);
    CHECK(msg.find('\n') == std::string::npos);
  }
}
