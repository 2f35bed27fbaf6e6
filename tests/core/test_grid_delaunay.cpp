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

TEST_CASE("core layered_delaunay: the grid's arrays on a lattice - valid and filling the box when sheared") {
  for (const auto& n : std::vector<std::array<int, 3>>{{2, 2, 2}, {5, 4, 6}, {7, 3, 2}, {6, 6, 6}}) {
    CAPTURE(n[0]);
    CAPTURE(n[1]);
    CAPTURE(n[2]);
    SimplexMesh<3> layered;
    REQUIRE(layered_delaunay(centres<3>(n), n[0] * n[1], layered));
    const SimplexMesh<3> whole = grid_delaunay<3>(n);
    CHECK(layered.cell == whole.cell);
    CHECK(layered.opp == whole.opp);
    // Sheared by whole and fractional shifts a layer: the cells, over the
    // unsheared points, are a valid mesh of the box (the shear is affine).
    for (const auto& [dx, dy] : std::vector<std::pair<double, double>>{{2, 1}, {-3, 0}, {1.25, -2.5}, {0.5, 0.375}}) {
      CAPTURE(dx);
      CAPTURE(dy);
      std::vector<Vec<3>> points = centres<3>(n), sheared = points;
      for (Vec<3>& p : sheared) p[0] -= dx * p[2], p[1] -= dy * p[2];
      SimplexMesh<3> mesh;
      REQUIRE(layered_delaunay(sheared, n[0] * n[1], mesh));
      CHECK(check_mesh<3>(mesh) == "");  // over the sheared points
      mesh.points = points;
      CHECK(check_mesh<3>(mesh) == "");
      CHECK(total_content<3>(mesh) == doctest::Approx(double(n[0] - 1) * (n[1] - 1) * (n[2] - 1)));
    }
  }
  SimplexMesh<3> untouched;
  CHECK_FALSE(layered_delaunay(centres<3>({4, 4, 1}), 16, untouched));  // one layer
  CHECK_FALSE(layered_delaunay(centres<3>({4, 4, 3}), 15, untouched));  // not whole layers
  CHECK(untouched.cell.empty());
}
