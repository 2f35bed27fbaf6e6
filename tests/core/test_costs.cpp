#include "core/costs.hpp"
#include "core_test_support.hpp"
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

TEST_CASE_TEMPLATE("simplex_gradient: an affine function's gradient is recovered on a skewed simplex", T,
                   core::test::Dim<2>, core::test::Dim<3>, core::test::Dim<4>) {
  constexpr int D = T::value;
  using V = Eigen::Matrix<double, D, 1>;
  // f(q) = g . q + 7 with g = (1, -2, 3, ...); a simplex neither axis-aligned nor regular.
  V g;
  for (int k = 0; k < D; ++k) g[k] = (k % 2 ? -1.0 : 1.0) * (k + 1);
  std::array<V, D + 1> p;
  std::array<double, D + 1> z;
  for (int i = 0; i <= D; ++i) {
    p[i] = V::Zero();
    if (i > 0) p[i][i - 1] = 1.0 + 0.5 * i;
    for (int k = 0; k < D; ++k) p[i][k] += 0.1 * ((i * 7 + k * 3) % 5);
    z[i] = g.dot(p[i]) + 7;
  }
  const V found = simplex_gradient<D>(p, z);
  for (int k = 0; k < D; ++k) CHECK(found[k] == doctest::Approx(g[k]));
}

TEST_CASE_TEMPLATE("simplex_content: the unit simplex has content 1/D!, scaled by the product of the axis scales", T,
                   core::test::Dim<2>, core::test::Dim<3>, core::test::Dim<4>) {
  constexpr int D = T::value;
  using V = Eigen::Matrix<double, D, 1>;
  std::array<V, D + 1> p;
  double factorial = 1, scaled = 1;
  for (int i = 0; i <= D; ++i) p[i] = V::Zero();
  for (int k = 0; k < D; ++k) p[k + 1][k] = 1, factorial *= k + 1;
  CHECK(simplex_content<D>(p) == doctest::Approx(1.0 / factorial));
  for (int k = 0; k < D; ++k) p[k + 1][k] = k + 2, scaled *= k + 2;
  CHECK(simplex_content<D>(p) == doctest::Approx(scaled / factorial));
  std::swap(p[0], p[1]);  // the content does not depend on the orientation
  CHECK(simplex_content<D>(p) == doctest::Approx(scaled / factorial));
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
