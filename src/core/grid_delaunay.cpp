#include "core/grid_delaunay.hpp"

#include "core/delaunay.hpp"
#include "core/lawson.hpp"
#include "util/error.hpp"
#include "util/prefaulted_image.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <string>
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

// The cells of the repeated pattern in canonical order without sorting.
// A cell's smallest id is its pattern cell's first corner (the corner
// offsets grow with the corner number), so cell (cube, p) is listed under
// the vertex v = cube + first corner of p, and the cells under one vertex
// come in one order for every vertex: the pattern cells sorted by their ids
// relative to the first. Near the grid's faces some of them are missing
// (their cube lies outside); which ones depends only on whether v is on
// the low face, inside or on the high face along each axis (its "class").
template <int D>
class CanonicalSlots {
 public:
  CanonicalSlots(const SimplexMesh<D>& cube, const std::vector<index_t>& offset, const std::array<int, D>& size)
      : size_(size) {
    T_ = cube.cell_count();
    first_corner_.resize(T_);
    for (int p = 0; p < T_; ++p) first_corner_[p] = cube.vertex(p, 0);
    // Under one vertex, cells compare by their ids less the vertex's.
    auto relative = [&](int p) {
      std::array<index_t, D> r;
      for (int k = 1; k <= D; ++k) r[k - 1] = offset[cube.vertex(p, k)] - offset[first_corner_[p]];
      return r;
    };
    std::vector<int> order(T_);
    for (int p = 0; p < T_; ++p) order[p] = p;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return relative(a) < relative(b); });
    int classes = 1;
    for (int k = 0; k < D; ++k) classes *= 3;
    rank_.assign(static_cast<std::size_t>(classes) * T_, -1);
    count_.assign(classes, 0);
    for (int c = 0; c < classes; ++c)
      for (int p : order) {
        bool valid = true;
        for (int k = 0, rest = c; k < D; ++k, rest /= 3) {
          const int face = rest % 3, bit = (first_corner_[p] >> k) & 1;
          valid = valid && !(bit == 1 && face == 0) && !(bit == 0 && face == 2);
        }
        if (valid) rank_[static_cast<std::size_t>(c) * T_ + p] = count_[c]++;
      }
    // Slots before each line along axis 0.
    lines_ = 1;
    for (int k = 1; k < D; ++k) lines_ *= static_cast<std::size_t>(size[k]);
    line_start_.resize(lines_ + 1, 0);
    for (std::size_t line = 0; line < lines_; ++line) {
      const int c = line_class(line);
      const std::size_t cells = count_[c] + static_cast<std::size_t>(size[0] - 2) * count_[c + 1] + count_[c + 2];
      line_start_[line + 1] = line_start_[line] + cells;
    }
  }

  int pattern_cells() const { return T_; }
  std::size_t cell_count() const { return line_start_.back(); }
  std::size_t lines() const { return lines_; }
  int first_corner(int p) const { return first_corner_[p]; }

  // The class of position (0, line's other coordinates): its own is +1
  // inside along axis 0, +2 at the high end.
  int line_class(std::size_t line) const {
    int c = 0;
    for (int k = 1, mul = 3; k < D; ++k, mul *= 3) {
      c += mul * face(static_cast<int>(line % size_[k]), k);
      line /= size_[k];
    }
    return c;
  }
  // The slot of pattern cell p listed under the vertex at pos, or -1 where
  // its cube lies outside the grid.
  long long slot(const std::array<int, D>& pos, int p) const {
    std::size_t line = 0;
    int c = 0;
    for (int k = D - 1; k >= 1; --k) {
      line = line * size_[k] + pos[k];
      c = 3 * c + face(pos[k], k);
    }
    c *= 3;
    const int x = pos[0];
    const int own = c + face(x, 0);
    const int r = rank_[static_cast<std::size_t>(own) * T_ + p];
    if (r < 0) return -1;
    const std::size_t before = x == 0 ? 0 : count_[c] + static_cast<std::size_t>(x - 1) * count_[c + 1];
    return static_cast<long long>(line_start_[line] + before) + r;
  }

 private:
  // Along axis k: 0 on the low face, 1 inside, 2 on the high face.
  int face(int pos, int k) const { return pos == 0 ? 0 : pos == size_[k] - 1 ? 2 : 1; }

  std::array<int, D> size_;
  int T_ = 0;
  std::vector<int> first_corner_, rank_;
  std::vector<std::size_t> count_, line_start_;
  std::size_t lines_ = 1;
};

}  // namespace

template <int D>
bool grid_delaunay_cells(const std::array<int, D>& size, std::vector<index_t>& cell, std::vector<index_t>& opp) {
  std::size_t n_points = 1;
  std::array<std::size_t, D> stride{};
  for (int k = 0; k < D; ++k) {
    if (size[k] < 2) return false;
    stride[k] = n_points;
    n_points *= static_cast<std::size_t>(size[k]);
  }
  // The cube pattern: CGAL on the 2^D corners; corner c = sum of bit k * e_k.
  std::vector<Vec<D>> corners(std::size_t(1) << D);
  for (std::size_t c = 0; c < corners.size(); ++c)
    for (int k = 0; k < D; ++k) corners[c][k] = 0.5 + static_cast<double>((c >> k) & 1);
  const SimplexMesh<D> cube = delaunay<D>(corners);
  const auto across = pattern_glue<D>(cube);
  if (across.empty()) return false;
  std::vector<index_t> offset(corners.size(), 0);
  for (std::size_t c = 0; c < corners.size(); ++c)
    for (int k = 0; k < D; ++k)
      if ((c >> k) & 1) offset[c] += static_cast<index_t>(stride[k]);
  const CanonicalSlots<D> slots(cube, offset, size);
  const int T = slots.pattern_cells();
  if (slots.cell_count() * (D + 1) > static_cast<std::size_t>(std::numeric_limits<index_t>::max()))
    throw Error("a grid of " + std::to_string(n_points) + " points has too many cells for 32-bit ids");

  const std::size_t spare = (D + 1) * lawson_pool_room(slots.cell_count());  // grid meshes are optimized next
  cell = prefaulted_zeros<index_t>((D + 1) * slots.cell_count(), spare);
  opp = prefaulted_zeros<index_t>((D + 1) * slots.cell_count(), spare);
  tbb::parallel_for(std::size_t(0), slots.lines(), [&](std::size_t line) {
    std::array<int, D> pos{};
    for (std::size_t k = 1, rest = line; k < D; ++k) pos[k] = static_cast<int>(rest % size[k]), rest /= size[k];
    for (int x = 0; x < size[0]; ++x) {
      pos[0] = x;
      const index_t v = static_cast<index_t>(line * size[0] + x);
      for (int p = 0; p < T; ++p) {
        const long long t = slots.slot(pos, p);
        if (t < 0) continue;
        const int m = slots.first_corner(p);
        std::array<int, D> cube_pos;  // the cube's lowest corner
        for (int k = 0; k < D; ++k) cube_pos[k] = pos[k] - ((m >> k) & 1);
        for (int k = 0; k <= D; ++k) {
          cell[(D + 1) * t + k] = v - offset[m] + offset[cube.vertex(p, k)];
          const Across& a = across[p][k];
          std::array<int, D> next = cube_pos;
          if (a.axis >= 0) next[a.axis] += a.step;
          index_t target = no_facet;
          if (a.axis < 0 || (next[a.axis] >= 0 && next[a.axis] < size[a.axis] - 1)) {
            const int mq = slots.first_corner(a.q);
            for (int j = 0; j < D; ++j) next[j] += (mq >> j) & 1;  // the anchor of cell q there
            target = static_cast<index_t>((D + 1) * slots.slot(next, a.q) + a.j);
          }
          opp[(D + 1) * t + k] = target;
        }
      }
    }
  });
  return true;
}

template <int D>
SimplexMesh<D> grid_delaunay(const std::array<int, D>& size) {
  std::size_t n_points = 1;
  for (int k = 0; k < D; ++k) n_points *= static_cast<std::size_t>(std::max(0, size[k]));
  std::vector<Vec<D>> points(n_points);
  tbb::parallel_for(std::size_t(0), n_points, [&](std::size_t id) {
    std::size_t rest = id;
    for (int k = 0; k < D; ++k) {
      points[id][k] = static_cast<double>(rest % size[k]) + 0.5;
      rest /= size[k];
    }
  });
  SimplexMesh<D> mesh;
  if (!grid_delaunay_cells<D>(size, mesh.cell, mesh.opp)) return delaunay<D>(points);  // flat
  mesh.points = std::move(points);
  return mesh;
}

template bool grid_delaunay_cells<2>(const std::array<int, 2>&, std::vector<index_t>&, std::vector<index_t>&);
template bool grid_delaunay_cells<3>(const std::array<int, 3>&, std::vector<index_t>&, std::vector<index_t>&);
template bool grid_delaunay_cells<4>(const std::array<int, 4>&, std::vector<index_t>&, std::vector<index_t>&);
template SimplexMesh<2> grid_delaunay<2>(const std::array<int, 2>&);
template SimplexMesh<3> grid_delaunay<3>(const std::array<int, 3>&);
template SimplexMesh<4> grid_delaunay<4>(const std::array<int, 4>&);

}  // namespace ddt::core
