#include "volume/tetrahedralization.hpp"

#include "core/delaunay.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>

namespace ddt {

using core::CellVertices;
using core::no_facet;
using core::SimplexMesh;

SimplexMesh<3> grid_tetrahedralization(int nx, int ny, int nz) {
  std::vector<core::Vec<3>> points(static_cast<std::size_t>(nx) * ny * nz);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        points[(static_cast<std::size_t>(z) * ny + y) * nx + x] = {x + 0.5, y + 0.5, z + 0.5};
  if (nx < 2 || ny < 2 || nz < 2) return core::delaunay<3>(points);

  // The cube pattern: CGAL on the 8 corners; corner c = dx + 2 dy + 4 dz.
  std::vector<core::Vec<3>> corners;
  for (int c = 0; c < 8; ++c) corners.push_back({0.5 + (c & 1), 0.5 + (c >> 1 & 1), 0.5 + (c >> 2 & 1)});
  const SimplexMesh<3> cube = core::delaunay<3>(corners);
  const int T = cube.cell_count();
  auto corner_of = [](index_t c, int axis) { return (c >> axis) & 1; };
  // Neighbour of facet i of pattern cell p: same cube (step 0) or the cube
  // one step along +-axis; (q, j) its cell and facet there, or q = -1 (hull).
  struct Across {
    int axis = -1, step = 0;
    int q = -1, j = -1;
  };
  std::vector<std::array<Across, 4>> across(T);
  for (int p = 0; p < T; ++p)
    for (int i = 0; i < 4; ++i) {
      Across& a = across[p][i];
      const index_t g = cube.opp[4 * p + i];
      if (g != no_facet) {
        a.q = core::cell_of<3>(g);
        a.j = core::local_of<3>(g);
        continue;
      }
      // A hull facet of the cube lies on one of its six faces.
      const core::FacetKey<3> f = core::facet_key(cube, 4 * p + i);
      for (int axis = 0; axis < 3 && a.axis < 0; ++axis)
        for (int side = 0; side < 2 && a.axis < 0; ++side)
          if (corner_of(f[0], axis) == side && corner_of(f[1], axis) == side && corner_of(f[2], axis) == side) {
            a.axis = axis;
            a.step = side ? 1 : -1;
          }
      // The same three points seen from the next cube: flip that axis bit.
      core::FacetKey<3> h;
      for (int k = 0; k < 3; ++k) h[k] = f[k] ^ (1 << a.axis);
      std::sort(h.begin(), h.end());
      for (int q = 0; q < T && a.q < 0; ++q)
        for (int j = 0; j < 4; ++j)
          if (cube.opp[4 * q + j] == no_facet && core::facet_key(cube, 4 * q + j) == h) {
            a.q = q;
            a.j = j;
            break;
          }
    }
  for (const auto& facets : across)
    for (const Across& a : facets)
      if (a.q < 0) return core::delaunay<3>(points);  // opposite cube faces split differently: never seen
  const std::size_t cx = nx - 1, cy = ny - 1, cz = nz - 1, n_cubes = cx * cy * cz;
  const index_t offset[8] = {0, 1, nx, nx + 1, nx * ny, nx * ny + 1, nx * ny + nx, nx * ny + nx + 1};
  struct Record {
    CellVertices<3> ids;
    index_t cube;
    std::int32_t p;
  };
  std::vector<Record> records(n_cubes * T);
  tbb::parallel_for(std::size_t(0), n_cubes, [&](std::size_t c) {
    const std::size_t x = c % cx, y = c / cx % cy, z = c / (cx * cy);
    const index_t base = static_cast<index_t>((z * ny + y) * nx + x);
    for (int p = 0; p < T; ++p) {
      Record& r = records[c * T + p];
      for (int k = 0; k < 4; ++k) r.ids[k] = base + offset[cube.vertex(p, k)];
      r.cube = static_cast<index_t>(c);
      r.p = p;
    }
  });
  tbb::parallel_sort(records.begin(), records.end(), [](const Record& a, const Record& b) { return a.ids < b.ids; });
  std::vector<index_t> slot_of(n_cubes * T);
  tbb::parallel_for(std::size_t(0), records.size(), [&](std::size_t t) {
    slot_of[static_cast<std::size_t>(records[t].cube) * T + records[t].p] = static_cast<index_t>(t);
  });

  SimplexMesh<3> mesh;
  mesh.points = std::move(points);
  mesh.cell.resize(4 * records.size());
  mesh.opp.resize(4 * records.size());
  tbb::parallel_for(std::size_t(0), records.size(), [&](std::size_t t) {
    const Record& r = records[t];
    const std::size_t c = r.cube;
    const long long pos[3] = {static_cast<long long>(c % cx), static_cast<long long>(c / cx % cy),
                              static_cast<long long>(c / (cx * cy))};
    const long long size[3] = {static_cast<long long>(cx), static_cast<long long>(cy), static_cast<long long>(cz)};
    for (int k = 0; k < 4; ++k) {
      mesh.cell[4 * t + k] = r.ids[k];
      const Across& a = across[r.p][k];
      index_t target = no_facet;
      if (a.axis < 0) {
        target = 4 * slot_of[c * T + a.q] + a.j;
      } else {
        long long next[3] = {pos[0], pos[1], pos[2]};
        next[a.axis] += a.step;
        if (next[a.axis] >= 0 && next[a.axis] < size[a.axis]) {
          const std::size_t c2 = static_cast<std::size_t>((next[2] * size[1] + next[1]) * size[0] + next[0]);
          target = 4 * slot_of[c2 * T + a.q] + a.j;
        }
      }
      mesh.opp[4 * t + k] = target;
    }
  });
  return mesh;
}

}  // namespace ddt
