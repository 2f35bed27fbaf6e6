#include "core/check_mesh.hpp"
#include "core/delaunay.hpp"
#include "core_test_support.hpp"

#include <doctest/doctest.h>

#include <numeric>

using namespace ddt;
using namespace ddt::core;
using ddt::core::test::Dim;

TEST_CASE_TEMPLATE("core delaunay: random points give a valid Delaunay mesh using every point", T, Dim<2>, Dim<3>,
                   Dim<4>) {
  constexpr int D = T::value;
  const auto points = test::random_points<D>(D == 4 ? 60 : 200, 21);
  const SimplexMesh<D> mesh = delaunay<D>(points);
  CHECK(check_mesh<D>(mesh) == "");
  CHECK(is_delaunay<D>(mesh));
  CHECK(mesh.free_slots.empty());
  std::vector<char> used(points.size(), 0);
  for (index_t v : mesh.cell) used[v] = 1;
  CHECK(std::accumulate(used.begin(), used.end(), 0) == static_cast<int>(points.size()));
}

TEST_CASE_TEMPLATE("core delaunay: the cells do not depend on the input order for points in general position", T,
                   Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  const auto points = test::random_points<D>(D == 4 ? 40 : 100, 8);
  const auto reference = test::cell_set(delaunay<D>(points));
  // Reversed input: vertex id v becomes n - 1 - v.
  const std::vector<Vec<D>> reversed(points.rbegin(), points.rend());
  const SimplexMesh<D> other = delaunay<D>(reversed);
  const index_t n = static_cast<index_t>(points.size());
  std::set<CellVertices<D>> mapped;
  for (CellVertices<D> v : test::cell_set(other)) {
    for (index_t& id : v) id = n - 1 - id;
    std::sort(v.begin(), v.end());
    mapped.insert(v);
  }
  CHECK(mapped == reference);
}

TEST_CASE_TEMPLATE("core delaunay: a lattice fills its box and is Delaunay despite the cospherical cells", T, Dim<2>,
                   Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  const int n = D == 4 ? 3 : 4;
  const SimplexMesh<D> mesh = delaunay<D>(test::grid_points<D>(n));
  CHECK(check_mesh<D>(mesh) == "");
  CHECK(is_delaunay<D>(mesh));
  double box = 1;
  for (int k = 0; k < D; ++k) box *= n - 1;
  CHECK(total_content(mesh) == doctest::Approx(box).epsilon(1e-12));
}

TEST_CASE_TEMPLATE("core delaunay: points in a hyperplane give no cells", T, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  auto points = test::random_points<D>(20, 2);
  for (auto& p : points) p[D - 1] = 0.5;
  CHECK(delaunay<D>(points).cell_count() == 0);
}
