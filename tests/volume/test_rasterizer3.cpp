#include "core/check_mesh.hpp"
#include "core/lawson.hpp"
#include "volume/rasterizer3.hpp"
#include "volume/tetrahedralization.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

using namespace ddt;
using Mesh3 = core::SimplexMesh<3>;

namespace {

VolumeGrid grid_for(int nx, int ny, int nz, double s) {
  VolumeGrid g;
  g.nx = static_cast<int>(std::lround(nx * s));
  g.ny = static_cast<int>(std::lround(ny * s));
  g.nz = static_cast<int>(std::lround(nz * s));
  g.scale_x = g.nx / double(nx), g.scale_y = g.ny / double(ny), g.scale_z = g.nz / double(nz);
  return g;
}

double linear(double x, double y, double z) { return 0.3 + 0.11 * x - 0.07 * y + 0.05 * z; }

// Random flips that keep the mesh valid, to leave the Delaunay mesh.
void scramble(Mesh3& m, int flips, unsigned seed) {
  std::mt19937 rng(seed);
  for (int done = 0, attempt = 0; done < flips && attempt < 50 * flips; ++attempt) {
    const index_t t = std::uniform_int_distribution<index_t>(0, m.slot_count() - 1)(rng);
    const unsigned mask = std::uniform_int_distribution<unsigned>(0, 15)(rng);
    if (!m.is_live(t) || std::popcount(mask) < 2 || std::popcount(mask) > 3) continue;
    core::FlipPlan<3> plans[2];
    if (core::propose_flip<3>(m, t, mask, plans, 2) == 0) continue;
    core::apply_flip<3>(m, plans[0]);
    ++done;
  }
}

}  // namespace

TEST_CASE("render_tetrahedra: a linear field is reproduced, inside the hull and (clamped) on the rim") {
  const int nx = 5, ny = 4, nz = 6;
  Mesh3 m = grid_tetrahedralization(nx, ny, nz);
  scramble(m, 300, 3);
  REQUIRE(core::check_mesh(m) == "");
  std::vector<float> values;
  for (const core::Vec<3>& p : m.points) values.push_back(static_cast<float>(linear(p[0], p[1], p[2])));
  for (const double s : {1.0, 2.5, 3.0, 4.0}) {
    CAPTURE(s);
    const VolumeGrid g = grid_for(nx, ny, nz, s);
    Render3Stats st;
    const Volume out = render_tetrahedra(m, values, g, &st);
    CHECK(st.uncovered == 0);
    CHECK(st.overcovered == 0);
    CHECK(st.owned + st.rim == static_cast<long long>(out.voxel_count()));
    double worst = 0;
    for (int Z = 0; Z < g.nz; ++Z)
      for (int Y = 0; Y < g.ny; ++Y)
        for (int X = 0; X < g.nx; ++X) {
          const double x = std::clamp((X + 0.5) / g.scale_x, 0.5, nx - 0.5);
          const double y = std::clamp((Y + 0.5) / g.scale_y, 0.5, ny - 0.5);
          const double z = std::clamp((Z + 0.5) / g.scale_z, 0.5, nz - 0.5);
          worst = std::max(worst, std::abs(out.at(X, Y, Z) - linear(x, y, z)));
        }
    CHECK(worst < 2e-6);
  }
}

TEST_CASE("render_tetrahedra: input samples are reproduced bit for bit where output voxels coincide (x3, x1)") {
  const int n = 6;
  Mesh3 m = grid_tetrahedralization(n, n, n);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> values(m.points.size());
  for (auto& v : values) v = u(rng);
  core::optimize_lawson<3>(m, values, 1, find_cost("variance"));
  for (const int s : {1, 3}) {
    const Volume out = render_tetrahedra(m, values, grid_for(n, n, n, s));
    int mismatches = 0;
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
          mismatches += out.at(s * x + s / 2, s * y + s / 2, s * z + s / 2) != values[(z * n + y) * n + x];
    CHECK(mismatches == 0);
  }
}

TEST_CASE("render_tetrahedra: every voxel has one owner, also at awkward scales") {
  Mesh3 m = grid_tetrahedralization(7, 3, 4);
  scramble(m, 200, 9);
  const std::vector<float> values(m.points.size(), 1.0f);
  for (const double s : {0.5, 1.7, 2.0, 3.3}) {
    CAPTURE(s);
    Render3Stats st;
    const Volume out = render_tetrahedra(m, values, grid_for(7, 3, 4, s), &st);
    CHECK(st.uncovered == 0);
    CHECK(st.overcovered == 0);
    CHECK(std::all_of(out.voxels.begin(), out.voxels.end(), [](float v) { return v == 1.0f; }));
  }
}

TEST_CASE("render_tetrahedra: a hull that is not a box, or no tets, is refused") {
  const Mesh3 tet = core::mesh_from_cells<3>({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 1, 2, 3}});
  VolumeGrid g;
  g.nx = g.ny = g.nz = 4;
  CHECK_THROWS(render_tetrahedra(tet, {0, 0, 0, 0}, g));
  CHECK_THROWS(render_tetrahedra(Mesh3{}, {}, g));
}
