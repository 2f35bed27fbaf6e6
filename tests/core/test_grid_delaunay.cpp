// core::grid_delaunay<D>: the one-cube pattern repeated equals CGAL's
// Delaunay triangulation (core::delaunay<D>) of the grid, array for array.
#include "core/check_mesh.hpp"
#include "core/delaunay.hpp"
#include "core/grid_delaunay.hpp"

#include <doctest/doctest.h>

#include <vector>

using namespace ddt;
using namespace ddt::core;

namespace {

template <int D>
std::vector<Vec<D>> centres(const std::array<int, D>& n) {
  std::size_t total = 1;
  for (int s : n) total *= s;
  std::vector<Vec<D>> points(total);
  for (std::size_t id = 0; id < total; ++id)
    for (std::size_t k = 0, rest = id; k < D; ++k) points[id][k] = static_cast<double>(rest % n[k]) + 0.5, rest /= n[k];
  return points;
}

template <int D>
void check_equal_to_cgal(const std::array<int, D>& n, int cells_per_cube) {
  const SimplexMesh<D> fast = grid_delaunay<D>(n);
  const SimplexMesh<D> cgal = delaunay<D>(centres<D>(n));
  CHECK(fast.points == cgal.points);
  CHECK(fast.cell == cgal.cell);
  CHECK(fast.opp == cgal.opp);
  CHECK(check_mesh<D>(fast) == "");
  CHECK(is_delaunay<D>(fast));
  long long cubes = 1;
  for (int s : n) cubes *= s - 1;
  CHECK(fast.cell_count() == cells_per_cube * cubes);
}

}  // namespace

TEST_CASE("core grid_delaunay<2>: the same arrays as CGAL's, two triangles per square") {
  for (const auto& n : std::vector<std::array<int, 2>>{{2, 2}, {5, 3}, {4, 7}, {2, 6}, {6, 2}, {31, 17}})
    check_equal_to_cgal<2>(n, 2);
}

TEST_CASE("core grid_delaunay_cells: the arrays of grid_delaunay, none for a flat grid") {
  std::vector<index_t> cell = {7}, opp = {7};
  CHECK_FALSE(grid_delaunay_cells<3>({4, 1, 4}, cell, opp));
  CHECK(cell == std::vector<index_t>{7});  // left as it was
  REQUIRE(grid_delaunay_cells<3>({5, 3, 4}, cell, opp));
  const SimplexMesh<3> whole = grid_delaunay<3>({5, 3, 4});
  CHECK(cell == whole.cell);
  CHECK(opp == whole.opp);
}

TEST_CASE("core grid_delaunay<3>: the same arrays as CGAL's, six tetrahedra per cube") {
  for (const auto& n : std::vector<std::array<int, 3>>{{2, 2, 2}, {3, 2, 2}, {5, 4, 6}, {7, 3, 2}, {6, 6, 6}, {2, 9, 3}}) {
    CAPTURE(n[0]);
    CAPTURE(n[1]);
    CAPTURE(n[2]);
    check_equal_to_cgal<3>(n, 6);
  }
  CHECK(grid_delaunay<3>({4, 4, 1}).cell_count() == 0);  // flat: no cells
}

TEST_CASE("core grid_delaunay<4>: the same arrays as CGAL's dD Delaunay, 24 simplices per cube") {
  for (const auto& n : std::vector<std::array<int, 4>>{{2, 2, 2, 2}, {3, 2, 2, 2}, {3, 3, 3, 3}, {2, 4, 3, 2}}) {
    CAPTURE(n[0]);
    CAPTURE(n[1]);
    CAPTURE(n[2]);
    CAPTURE(n[3]);
    check_equal_to_cgal<4>(n, 24);
  }
  CHECK(grid_delaunay<4>({3, 3, 1, 3}).cell_count() == 0);
}
