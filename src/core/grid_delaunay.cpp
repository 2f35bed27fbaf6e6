#include "core/grid_delaunay.hpp"

#include "core/delaunay.hpp"
#include "util/prefaulted_image.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <vector>

namespace ddt::core {
namespace {

// Neighbour of facet i of pattern cell p: in the same cube (axis < 0) or in
// the cube one step along +-axis; (q, j) is the cell and facet there.
struct Across {
  int axis = -1, step = 0;
  int q = -1, j = -1;
};

// The glue of the one-cube pattern; empty when some hull facet of the cube
// has no partner on the opposite face (opposite faces split differently:
// never seen, and then the caller runs CGAL on the whole grid).
template <int D>
std::vector<std::array<Across, D + 1>> pattern_glue(const SimplexMesh<D>& cube) {
  const int T = cube.cell_count();
  std::vector<std::array<Across, D + 1>> across(T);
  for (int p = 0; p < T; ++p)
    for (int i = 0; i <= D; ++i) {
      Across& a = across[p][i];
      const index_t g = cube.opp[(D + 1) * p + i];
      if (g != no_facet) {
        a.q = cell_of<D>(g);
        a.j = local_of<D>(g);
        continue;
      }
      // A hull facet of the cube lies in one of its 2D faces: all its
      // corners share one bit. Corner c has bit k = its offset along axis k.
      const FacetKey<D> f = facet_key(cube, (D + 1) * p + i);
      for (int axis = 0; axis < D && a.axis < 0; ++axis)
        for (int side = 0; side < 2 && a.axis < 0; ++side) {
          bool on = true;
          for (index_t c : f) on = on && ((c >> axis) & 1) == side;
          if (on) a.axis = axis, a.step = side ? 1 : -1;
        }
      if (a.axis < 0) return {};
      // The same corners seen from the next cube: that axis bit flipped.
      FacetKey<D> h;
      for (int k = 0; k < D; ++k) h[k] = f[k] ^ (1 << a.axis);
      std::sort(h.begin(), h.end());
      for (int q = 0; q < T && a.q < 0; ++q)
        for (int j = 0; j <= D; ++j)
          if (cube.opp[(D + 1) * q + j] == no_facet && facet_key(cube, (D + 1) * q + j) == h) {
            a.q = q, a.j = j;
            break;
          }
      if (a.q < 0) return {};
    }
  return across;
}

}  // namespace

template <int D>
SimplexMesh<D> grid_delaunay(const std::array<int, D>& size) {
  std::size_t n_points = 1, n_cubes = 1;
  std::array<std::size_t, D> stride{}, cubes{};
  bool flat = false;
  for (int k = 0; k < D; ++k) {
    stride[k] = n_points;
    n_points *= static_cast<std::size_t>(size[k]);
    flat = flat || size[k] < 2;
    cubes[k] = size[k] > 1 ? static_cast<std::size_t>(size[k] - 1) : 0;
    n_cubes *= cubes[k];
  }
  std::vector<Vec<D>> points(n_points);
  tbb::parallel_for(std::size_t(0), n_points, [&](std::size_t id) {
    std::size_t rest = id;
    for (int k = 0; k < D; ++k) {
      points[id][k] = static_cast<double>(rest % size[k]) + 0.5;
      rest /= size[k];
    }
  });
  if (flat) return delaunay<D>(points);

  // The cube pattern: CGAL on the 2^D corners; corner c = sum of bit k * e_k.
  std::vector<Vec<D>> corners(std::size_t(1) << D);
  for (std::size_t c = 0; c < corners.size(); ++c)
    for (int k = 0; k < D; ++k) corners[c][k] = 0.5 + static_cast<double>((c >> k) & 1);
  const SimplexMesh<D> cube = delaunay<D>(corners);
  const auto across = pattern_glue<D>(cube);
  if (across.empty()) return delaunay<D>(points);
  const int T = cube.cell_count();
  std::vector<index_t> offset(corners.size(), 0);
  for (std::size_t c = 0; c < corners.size(); ++c)
    for (int k = 0; k < D; ++k)
      if ((c >> k) & 1) offset[c] += static_cast<index_t>(stride[k]);

  struct Record {
    CellVertices<D> ids;
    index_t cube;
    std::int32_t p;
  };
  auto cube_base = [&](std::size_t c) {
    std::size_t base = 0, rest = c;
    for (int k = 0; k < D; ++k) {
      base += (rest % cubes[k]) * stride[k];
      rest /= cubes[k];
    }
    return static_cast<index_t>(base);
  };
  std::vector<Record> records = prefaulted_zeros<Record>(n_cubes * T);
  tbb::parallel_for(std::size_t(0), n_cubes, [&](std::size_t c) {
    const index_t base = cube_base(c);
    for (int p = 0; p < T; ++p) {
      Record& r = records[c * T + p];
      for (int k = 0; k <= D; ++k) r.ids[k] = base + offset[cube.vertex(p, k)];
      r.cube = static_cast<index_t>(c);
      r.p = p;
    }
  });
  tbb::parallel_sort(records.begin(), records.end(), [](const Record& a, const Record& b) { return a.ids < b.ids; });
  std::vector<index_t> slot_of = prefaulted_zeros<index_t>(n_cubes * T);
  tbb::parallel_for(std::size_t(0), records.size(), [&](std::size_t t) {
    slot_of[static_cast<std::size_t>(records[t].cube) * T + records[t].p] = static_cast<index_t>(t);
  });

  SimplexMesh<D> mesh;
  mesh.points = std::move(points);
  mesh.cell = prefaulted_zeros<index_t>((D + 1) * records.size());
  mesh.opp = prefaulted_zeros<index_t>((D + 1) * records.size());
  tbb::parallel_for(std::size_t(0), records.size(), [&](std::size_t t) {
    const Record& r = records[t];
    const std::size_t c = r.cube;
    std::array<std::size_t, D> pos;
    std::size_t cube_stride[D];
    for (std::size_t k = 0, rest = c, s = 1; k < D; ++k) {
      pos[k] = rest % cubes[k];
      rest /= cubes[k];
      cube_stride[k] = s;
      s *= cubes[k];
    }
    for (int k = 0; k <= D; ++k) {
      mesh.cell[(D + 1) * t + k] = r.ids[k];
      const Across& a = across[r.p][k];
      index_t target = no_facet;
      if (a.axis < 0) {
        target = (D + 1) * slot_of[c * T + a.q] + a.j;
      } else if (a.step > 0 ? pos[a.axis] + 1 < cubes[a.axis] : pos[a.axis] > 0) {
        const std::size_t c2 = a.step > 0 ? c + cube_stride[a.axis] : c - cube_stride[a.axis];
        target = (D + 1) * slot_of[c2 * T + a.q] + a.j;
      }
      mesh.opp[(D + 1) * t + k] = target;
    }
  });
  return mesh;
}

template SimplexMesh<2> grid_delaunay<2>(const std::array<int, 2>&);
template SimplexMesh<3> grid_delaunay<3>(const std::array<int, 3>&);
template SimplexMesh<4> grid_delaunay<4>(const std::array<int, 4>&);

}  // namespace ddt::core
