#include "core/check_mesh.hpp"
#include "core/delaunay.hpp"
#include "volume/tetrahedralization.hpp"

#include <doctest/doctest.h>

#include <array>
#include <vector>

using namespace ddt;

TEST_CASE("grid_tetrahedralization: the same arrays as core::delaunay<3> (CGAL) of the voxel centres") {
  for (const auto& n : std::vector<std::array<int, 3>>{{2, 2, 2}, {3, 2, 2}, {5, 4, 6}, {7, 3, 2}, {6, 6, 6}, {2, 9, 3}}) {
    CAPTURE(n[0]);
    CAPTURE(n[1]);
    CAPTURE(n[2]);
    std::vector<core::Vec<3>> points;
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x) points.push_back({x + 0.5, y + 0.5, z + 0.5});
    const core::SimplexMesh<3> fast = grid_tetrahedralization(n[0], n[1], n[2]);
    const core::SimplexMesh<3> cgal = core::delaunay<3>(points);
    CHECK(fast.points == cgal.points);
    CHECK(fast.cell == cgal.cell);
    CHECK(fast.opp == cgal.opp);
    CHECK(core::check_mesh(fast) == "");
    CHECK(core::is_delaunay(fast));
    CHECK(fast.cell_count() == 6 * (n[0] - 1) * (n[1] - 1) * (n[2] - 1));
  }
  CHECK(grid_tetrahedralization(4, 4, 1).cell_count() == 0);  // flat: no tetrahedra
}
