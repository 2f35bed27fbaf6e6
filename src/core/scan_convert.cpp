#include "core/scan_convert.hpp"

#include "core/predicates.hpp"
#include "core/scan_fill_rule.hpp"
#include "util/error.hpp"
#include "util/prefaulted_image.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cmath>
#include <map>
#include <string>

namespace ddt::core {
namespace {

using namespace fill_rule;

// The points of a section (at most the crossings of the vertex pairs of
// the previous section; 16 covers D <= 4).
template <int D>
struct Section {
  std::array<Vec<D>, 16> p;
  int n = 0;
};

// Everything the scan of one cell reads.
template <int D>
struct Scan {
  const ScanGrid<D>& grid;
  const std::array<std::vector<double>, D>& coord;  // sample positions per axis
  std::array<std::size_t, D> stride;                // of the output, in samples
  double tol;
  bool lattice;
  int K;
  float* out;
  unsigned char* hits;
  const IntegerFrame<D>& frame;

  // Indices of the window's samples along `axis` whose coordinate may lie
  // in [lo, hi].
  void index_range(int axis, double lo, double hi, int& first, int& last) const {
    const double scale = grid.scale[axis];
    const double phase = grid.phase[axis];
    first = std::max(0, ceil_int((lo - tol) * scale - phase) - grid.first[axis]);
    last = std::min(grid.size[axis] - 1, floor_int((hi + tol) * scale - phase) - grid.first[axis]);
  }

  // std::floor and std::ceil are library calls without SSE4.1, and this
  // runs for every row of every cell. x is a sample index (clamped: the
  // ranges are clamped to the window after).
  static int floor_int(double x) {
    x = std::clamp(x, -1e9, 1e9);
    const int i = static_cast<int>(x);
    return i - (x < i);
  }
  static int ceil_int(double x) {
    x = std::clamp(x, -1e9, 1e9);
    const int i = static_cast<int>(x);
    return i + (x > i);
  }
};

// The section of the point set `from` by the hyperplane x_axis = c.
template <int D>
void cut(const Vec<D>* from, int n, int axis, double c, Section<D>& to) {
  to.n = 0;
  for (int i = 0; i < n; ++i) {
    const double di = from[i][axis] - c;
    if (di == 0) {
      to.p[to.n++] = from[i];
      continue;
    }
    for (int j = i + 1; j < n; ++j) {
      const double dj = from[j][axis] - c;
      if ((di > 0 && dj < 0) || (di < 0 && dj > 0)) {
        const double t = di / (di - dj);
        Vec<D>& q = to.p[to.n++];
        for (int k = 0; k < D; ++k) q[k] = from[i][k] + t * (from[j][k] - from[i][k]);
        q[axis] = c;
      }
    }
  }
}

// Writes samples X0..X1 of a row (along axis s.order[0]), all owned by the
// cell. Channels: the compile-time count (1: scalars) or 0 for scan.K.
// Both paths apply the one exact fill rule, so no sample has two owners
// (ScanStats::overcovered counts any that would); the integer frame's rows
// (Exact) count with a plain add, the rare floating-point cells keep an
// atomic one.
template <int D, int Channels, bool Exact>
void interpolate_row(const Scan<D>& scan, const CellSetup<D>& s, const double* z0, const double* dz, const Vec<D>& q,
                     std::size_t row_base, int X0, int X1) {
  const int K = Channels > 0 ? Channels : scan.K;
  const int row = s.order[0];
  const std::vector<double>& xs = scan.coord[row];
  const std::size_t step = scan.stride[row];
  Vec<D> pq;
  for (int k = 0; k < D; ++k) pq[k] = q[k] - s.p[0][k];
  for (int X = X0; X <= X1; ++X) {
    pq[row] = xs[X] - s.p[0][row];
    double w[D + 1];
    for (int i = 1; i <= D; ++i) {
      double dot = s.raw[i][0] * pq[0];
      for (int k = 1; k < D; ++k) dot += s.raw[i][k] * pq[k];
      w[i] = dot / s.den[i];
    }
    const std::size_t idx = row_base + X * step;
    float* o = scan.out + idx * K;
    if (s.patch) {
      w[0] = 1;
      for (int i = 1; i <= D; ++i) w[0] -= w[i];
      for (int c = 0; c < K; ++c) o[c] = static_cast<float>(eval_cubic<D>(s.patch + c * cubic_controls<D>, w));
    } else {
      for (int c = 0; c < K; ++c) {
        double v = z0[c];
        for (int i = 1; i <= D; ++i) v += w[i] * dz[(i - 1) * K + c];
        o[c] = static_cast<float>(v);
      }
    }
    if constexpr (Exact)  // the exact fill rule gives every sample one owner
      ++scan.hits[idx];
    else
      std::atomic_ref<unsigned char>(scan.hits[idx]).fetch_add(1, std::memory_order_relaxed);
  }
}

// One row along axis s.order[0] at the other coordinates of q: the
// floating-point segment inside the cell, trimmed exactly at both ends (the
// owned samples of a row are contiguous), then interpolated.
template <int D>
void scan_row(const Scan<D>& scan, const CellSetup<D>& s, const double* z0, const double* dz, Vec<D> q,
              std::size_t row_base, int xb0, int xb1) {
  const int row = s.order[0];
  double x_lo = s.lo[row], x_hi = s.hi[row];
  for (int i = 0; i <= D; ++i) {
    double rest = s.off[i];
    for (int k = 0; k < D; ++k)
      if (k != row) rest += s.unit[i][k] * q[k];
    const double nx = s.unit[i][row];
    if (s.inv_row[i] == 0) {
      if (rest < -scan.tol) return;
    } else if (nx > 0) {
      x_lo = std::max(x_lo, -rest * s.inv_row[i]);
    } else {
      x_hi = std::min(x_hi, -rest * s.inv_row[i]);
    }
  }
  if (x_lo > x_hi + 2 * scan.tol) return;
  int X0, X1;
  scan.index_range(row, x_lo, x_hi, X0, X1);
  X0 = std::max(X0, xb0);
  X1 = std::min(X1, xb1);
  const std::vector<double>& xs = scan.coord[row];
  for (; X0 <= X1; ++X0) {
    q[row] = xs[X0];
    if (inside<D>(s, q, scan.tol, scan.lattice)) break;
  }
  for (; X1 >= X0; --X1) {
    q[row] = xs[X1];
    if (inside<D>(s, q, scan.tol, scan.lattice)) break;
  }
  if (X0 > X1) return;
  if (scan.K == 1)
    interpolate_row<D, 1, false>(scan, s, z0, dz, q, row_base, X0, X1);
  else
    interpolate_row<D, 0, false>(scan, s, z0, dz, q, row_base, X0, X1);
}

// scan_row in the integer frame: the side of facet i at sample xb0 + t is
// the integer A t + B, so each facet bounds t exactly (an estimate by one
// multiplication, then corrected by exact tests). The fill rule keeps a
// sample where A t + B > 0, or = 0 with the facet's tie-break +1: in
// integers, A t + B - (tie > 0 ? 0 : 1) >= 0. S: the scaled coordinates of
// the row (all axes but the row's).
template <int D>
void scan_row_exact(const Scan<D>& scan, const CellSetup<D>& s, const IntegerCell<D>& cell, const double* z0,
                    const double* dz, const Vec<D>& q, const std::array<std::int64_t, D>& S, std::size_t row_base,
                    int xb0, int xb1) {
  const int row = s.order[0];
  const std::int64_t step = scan.frame.sample_step[row];
  const std::int64_t s0 = scan.frame.sample_base[row] + std::int64_t(xb0) * step;
  const std::int64_t W = xb1 - xb0;
  std::int64_t t_lo = 0, t_hi = W;
  for (int i = 0; i <= D && t_lo <= t_hi; ++i) {
    const int base = i == 0 ? 1 : 0;
    const std::array<std::int64_t, D>& n = cell.normal[i];
    std::int64_t B = cell.tie[i] > 0 ? 0 : -1;
    for (int k = 0; k < D; ++k) B += n[k] * ((k == row ? s0 : S[k]) - cell.v[base][k]);
    const std::int64_t A = n[row] * step;
    if (A == 0) {  // parallel to the row: all or nothing
      if (B >= 0) continue;
      return;
    }
    const double estimate = std::clamp(-double(B) * cell.inv_row_slope[i], -2.0, double(W) + 2.0);
    if (A > 0) {  // A t + B >= 0 from some t on
      std::int64_t t = Scan<D>::ceil_int(estimate);
      while (t > t_lo && A * (t - 1) + B >= 0) --t;
      while (t <= t_hi && A * t + B < 0) ++t;
      t_lo = std::max(t_lo, t);
    } else {  // up to some t
      std::int64_t t = Scan<D>::floor_int(estimate);
      while (t < t_hi && A * (t + 1) + B >= 0) ++t;
      while (t >= t_lo && A * t + B < 0) --t;
      t_hi = std::min(t_hi, t);
    }
  }
  if (t_lo > t_hi) return;
  const int X0 = xb0 + static_cast<int>(t_lo), X1 = xb0 + static_cast<int>(t_hi);
  if (scan.K == 1)
    interpolate_row<D, 1, true>(scan, s, z0, dz, q, row_base, X0, X1);
  else
    interpolate_row<D, 0, true>(scan, s, z0, dz, q, row_base, X0, X1);
}

// The samples along axis s.order[L] (L >= 1) of the section `sec` (the
// vertices for L = D - 1), each one's row or sub-section in turn.
template <int D, int L>
void scan_level(const Scan<D>& scan, const CellSetup<D>& s, const IntegerCell<D>* cell, const double* z0,
                const double* dz, const Vec<D>* sec, int n, Vec<D> q, std::array<std::int64_t, D> S, std::size_t base,
                const std::array<int, D>& box_first, const std::array<int, D>& box_last) {
  const int axis = s.order[L];
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < n; ++i) lo = std::min(lo, sec[i][axis]), hi = std::max(hi, sec[i][axis]);
  int I0 = box_first[axis], I1 = box_last[axis];
  if (lo <= hi) {
    int a, b;
    scan.index_range(axis, lo, hi, a, b);
    I0 = std::max(I0, a), I1 = std::min(I1, b);
  }
  for (int I = I0; I <= I1; ++I) {
    q[axis] = scan.coord[axis][I];
    S[axis] = scan.frame.sample_base[axis] + std::int64_t(I) * scan.frame.sample_step[axis];
    const std::size_t next = base + I * scan.stride[axis];
    if constexpr (L == 1) {
      const int row = s.order[0];
      if (cell)
        scan_row_exact<D>(scan, s, *cell, z0, dz, q, S, next, box_first[row], box_last[row]);
      else
        scan_row<D>(scan, s, z0, dz, q, next, box_first[row], box_last[row]);
    } else {
      Section<D> cross;
      cut<D>(sec, n, axis, q[axis], cross);
      scan_level<D, L - 1>(scan, s, cell, z0, dz, cross.p.data(), cross.n, q, S, next, box_first, box_last);
    }
  }
}

// The axes of a cell's rows and levels: the rows along the axis where its
// bounding box holds the most samples (the fewest rows: ties keep the
// lower axis), the levels along the others in increasing order.
template <int D>
std::array<int, D> row_order(const std::array<int, D>& first, const std::array<int, D>& last) {
  int row = 0;
  for (int k = 1; k < D; ++k)
    if (last[k] - first[k] > last[row] - first[row]) row = k;
  std::array<int, D> order;
  order[0] = row;
  for (int k = 0, n = 1; k < D; ++k)
    if (k != row) order[n++] = k;
  return order;
}

// The hull box's faces: 2D of them, face 2 axis + side (0 min, 1 max);
// each as the field of its hull facets over the window's in-plane samples.
template <int D>
std::vector<std::vector<float>> render_box_faces(const SimplexMesh<D>& mesh, const std::vector<float>& values, int K,
                                                 const ScanGrid<D>& grid, const Vec<D>& lo, const Vec<D>& hi,
                                                 const std::vector<float>* gradients) {
  std::vector<std::vector<float>> faces(2 * D);
  if constexpr (D == 1) {
    // The faces of a segment's box are its end points: their values.
    for (const auto& v : mesh.cell)
      for (int side = 0; side < 2; ++side)
        if (v != no_vertex && mesh.points[v][0] == (side ? hi[0] : lo[0]) && faces[side].empty())
          faces[side].assign(values.begin() + static_cast<std::ptrdiff_t>(v) * K,
                             values.begin() + static_cast<std::ptrdiff_t>(v + 1) * K);
  } else {
    std::vector<std::vector<CellVertices<D - 1>>> facets(2 * D);
    for (index_t c = 0; c < mesh.slot_count(); ++c) {
      if (!mesh.is_live(c)) continue;
      for (int i = 0; i <= D; ++i) {
        if (mesh.opp[(D + 1) * static_cast<std::size_t>(c) + i] != no_facet) continue;
        CellVertices<D - 1> f;
        for (int j = 0, n = 0; j <= D; ++j)
          if (j != i) f[n++] = mesh.vertex(c, j);
        int which = -1;
        for (int axis = 0; axis < D && which < 0; ++axis)
          for (int side = 0; side < 2 && which < 0; ++side) {
            const double plane = side ? hi[axis] : lo[axis];
            bool on = true;
            for (index_t v : f) on = on && mesh.points[v][axis] == plane;
            if (on) which = 2 * axis + side;
          }
        if (which < 0) throw Error("scan_convert: the mesh's hull is not an axis-aligned box");
        facets[which].push_back(f);
      }
    }
    for (int which = 0; which < 2 * D; ++which) {
      const int axis = which / 2;
      if (facets[which].empty()) throw Error("scan_convert: the mesh's hull is not an axis-aligned box");
      std::map<index_t, index_t> local;
      std::vector<Vec<D - 1>> points;
      std::vector<float> face_values, face_gradients;  // the gradients' in-plane components
      for (CellVertices<D - 1>& f : facets[which])
        for (index_t& id : f) {
          auto [it, fresh] = local.emplace(id, static_cast<index_t>(points.size()));
          if (fresh) {
            Vec<D - 1> p;
            for (int k = 0, n = 0; k < D; ++k)
              if (k != axis) p[n++] = mesh.points[id][k];
            points.push_back(p);
            face_values.insert(face_values.end(), values.begin() + static_cast<std::ptrdiff_t>(id) * K,
                               values.begin() + static_cast<std::ptrdiff_t>(id + 1) * K);
            if (gradients)
              for (int c = 0; c < K; ++c)
                for (int k = 0; k < D; ++k)
                  if (k != axis) face_gradients.push_back((*gradients)[(static_cast<std::size_t>(id) * K + c) * D + k]);
          }
          id = it->second;
        }
      const SimplexMesh<D - 1> face = mesh_from_cells<D - 1>(std::move(points), facets[which]);
      ScanGrid<D - 1> g;
      for (int k = 0, n = 0; k < D; ++k)
        if (k != axis)
          g.size[n] = grid.size[k], g.scale[n] = grid.scale[k], g.first[n] = grid.first[k], g.phase[n] = grid.phase[k], ++n;
      faces[which] = scan_convert<D - 1>(face, face_values, K, g, nullptr, gradients ? &face_gradients : nullptr);
    }
  }
  return faces;
}

}  // namespace

template <int D>
std::vector<float> scan_convert(const SimplexMesh<D>& mesh, const std::vector<float>& values, int K,
                                const ScanGrid<D>& grid, ScanStats* stats, const std::vector<float>* gradients) {
  if (K < 1) throw Error("scan_convert: at least one channel is needed");
  if (values.size() != mesh.points.size() * static_cast<std::size_t>(K))
    throw Error("scan_convert: the values do not match the mesh's points and channels");
  if (gradients && gradients->size() != values.size() * D)
    throw Error("scan_convert: the gradients do not match the mesh's points and channels");
  if (mesh.cell_count() == 0) throw Error("scan_convert: the mesh has no cells");
  for (int k = 0; k < D; ++k)
    if (grid.size[k] < 0 || !(grid.scale[k] > 0)) throw Error("scan_convert: bad grid");
  ScanStats local;
  Vec<D> lo, hi;
  lo.fill(INFINITY);
  hi.fill(-INFINITY);
  for (index_t c = 0; c < mesh.slot_count(); ++c) {
    if (!mesh.is_live(c)) continue;
    ++local.cells;
    for (int i = 0; i <= D; ++i)
      for (int k = 0; k < D; ++k) {
        const double x = mesh.points[mesh.vertex(c, i)][k];
        lo[k] = std::min(lo[k], x), hi[k] = std::max(hi[k], x);
      }
  }
  const std::vector<std::vector<float>> faces = render_box_faces<D>(mesh, values, K, grid, lo, hi, gradients);

  std::array<std::vector<double>, D> coord;
  std::array<std::size_t, D> stride;
  double extent = 1, magnitude = 0;
  for (int k = 0; k < D; ++k) {
    coord[k].resize(grid.size[k]);
    for (int X = 0; X < grid.size[k]; ++X) coord[k][X] = (grid.first[k] + X + grid.phase[k]) / grid.scale[k];
    stride[k] = k == 0 ? 1 : stride[k - 1] * grid.size[k - 1];
    extent = std::max(extent, hi[k] - lo[k]);
    magnitude += std::abs(lo[k]);
  }
  const std::size_t count = grid.count();
  std::vector<float> out = prefaulted_zeros<float>(count * K);
  std::vector<unsigned char> hits = prefaulted_zeros<unsigned char>(count);
  const IntegerFrame<D> frame = integer_frame<D>(mesh.points, grid);
  const Scan<D> scan{grid, coord, stride, 1e-9 * (extent + magnitude), lattice_exact<D>(mesh.points), K,
                     out.data(), hits.data(), frame};

  if (count > 0)
    tbb::parallel_for(tbb::blocked_range<index_t>(0, mesh.slot_count(), 256), [&](const tbb::blocked_range<index_t>& r) {
      std::vector<double> z0(K), dz(static_cast<std::size_t>(D) * K);
      std::vector<double> patch(gradients ? static_cast<std::size_t>(K) * cubic_controls<D> : 0);
      for (index_t c = r.begin(); c != r.end(); ++c) {
        if (!mesh.is_live(c)) continue;
        CellSetup<D> s;
        for (int i = 0; i <= D; ++i) s.p[i] = mesh.points[mesh.vertex(c, i)];
        for (int k = 0; k < D; ++k) {
          s.lo[k] = s.hi[k] = s.p[0][k];
          for (int i = 1; i <= D; ++i) s.lo[k] = std::min(s.lo[k], s.p[i][k]), s.hi[k] = std::max(s.hi[k], s.p[i][k]);
        }
        std::array<int, D> first, last;
        bool empty = false;
        for (int k = 0; k < D; ++k) {
          scan.index_range(k, s.lo[k], s.hi[k], first[k], last[k]);
          empty = empty || first[k] > last[k];
        }
        if (empty) continue;
        s.order = row_order<D>(first, last);
        IntegerCell<D> exact_cell;
        const IntegerCell<D>* cell = frame.valid && integer_cell<D>(frame, s, exact_cell) ? &exact_cell : nullptr;
        setup_cell<D>(s, cell == nullptr);
        for (int ch = 0; ch < K; ++ch) {
          z0[ch] = values[static_cast<std::size_t>(mesh.vertex(c, 0)) * K + ch];
          for (int i = 1; i <= D; ++i)
            dz[(i - 1) * K + ch] = double(values[static_cast<std::size_t>(mesh.vertex(c, i)) * K + ch]) - z0[ch];
        }
        if (gradients) {
          for (int ch = 0; ch < K; ++ch) {
            double z[D + 1], g[(D + 1) * D];
            for (int i = 0; i <= D; ++i) {
              const std::size_t at = static_cast<std::size_t>(mesh.vertex(c, i)) * K + ch;
              z[i] = values[at];
              for (int k = 0; k < D; ++k) g[i * D + k] = (*gradients)[at * D + k];
            }
            cubic_patch<D>(s.p, z, g, patch.data() + ch * cubic_controls<D>);
          }
          s.patch = patch.data();
        }
        Vec<D> q{};
        if constexpr (D == 1) {
          if (cell)
            scan_row_exact<D>(scan, s, *cell, z0.data(), dz.data(), q, {}, 0, first[0], last[0]);
          else
            scan_row<D>(scan, s, z0.data(), dz.data(), q, 0, first[0], last[0]);
        } else {
          scan_level<D, D - 1>(scan, s, cell, z0.data(), dz.data(), s.p.data(), D + 1, q, {}, 0, first, last);
        }
      }
    });

  // Samples no simplex owns: outside the hull (or on it) -> the face value
  // at the clamped position.
  const int slowest = D - 1;
  std::atomic<long long> owned{0}, rim{0}, uncovered{0}, overcovered{0};
  const std::size_t per_slice = count / std::max(1, grid.size[slowest]);
  tbb::parallel_for(0, grid.size[slowest], [&](int Z) {
    long long n_owned = 0, n_rim = 0, n_uncovered = 0, n_over = 0;
    std::array<int, D> index{};
    index[slowest] = Z;
    for (std::size_t j = 0; j < per_slice; ++j) {
      const std::size_t idx = Z * per_slice + j;
      if (hits[idx] == 1) {
        ++n_owned;
        continue;
      }
      if (hits[idx] > 1) {
        ++n_over;
        continue;
      }
      for (int k = 0, rest = static_cast<int>(j); k < slowest; ++k) index[k] = rest % grid.size[k], rest /= grid.size[k];
      int which = -1;
      for (int axis = 0; axis < D && which < 0; ++axis) {
        const double x = coord[axis][index[axis]];
        if (x <= lo[axis]) which = 2 * axis;
        else if (x >= hi[axis]) which = 2 * axis + 1;
      }
      if (which < 0) {
        ++n_uncovered;
        continue;
      }
      const int axis = which / 2;
      std::size_t face_index = 0, face_stride = 1;
      for (int k = 0; k < D; ++k)
        if (k != axis) face_index += index[k] * face_stride, face_stride *= grid.size[k];
      for (int ch = 0; ch < K; ++ch) out[idx * K + ch] = faces[which][face_index * K + ch];
      ++n_rim;
    }
    owned += n_owned, rim += n_rim, uncovered += n_uncovered, overcovered += n_over;
  });
  local.owned = owned;
  local.rim = rim;
  local.uncovered = uncovered;
  local.overcovered = overcovered;
  if (local.uncovered > 0) {
    // Only slivers collapsed by rounding could leave a hole: copy the
    // neighbour along axis 0.
    for (std::size_t idx = 0; idx < count; ++idx) {
      if (hits[idx] != 0) continue;
      std::size_t rest = idx;
      bool in = true;
      int X0 = 0;
      for (int k = 0; k < D; ++k) {
        const int I = static_cast<int>(rest % grid.size[k]);
        rest /= grid.size[k];
        if (k == 0) X0 = I;
        in = in && coord[k][I] > lo[k] && coord[k][I] < hi[k];
      }
      if (!in || grid.size[0] < 2) continue;
      const std::size_t from = X0 > 0 ? idx - 1 : idx + 1;
      for (int ch = 0; ch < K; ++ch) out[idx * K + ch] = out[from * K + ch];
    }
  }
  if (stats) *stats = local;
  return out;
}

template std::vector<float> scan_convert<1>(const SimplexMesh<1>&, const std::vector<float>&, int, const ScanGrid<1>&,
                                            ScanStats*, const std::vector<float>*);
template std::vector<float> scan_convert<2>(const SimplexMesh<2>&, const std::vector<float>&, int, const ScanGrid<2>&,
                                            ScanStats*, const std::vector<float>*);
template std::vector<float> scan_convert<3>(const SimplexMesh<3>&, const std::vector<float>&, int, const ScanGrid<3>&,
                                            ScanStats*, const std::vector<float>*);
template std::vector<float> scan_convert<4>(const SimplexMesh<4>&, const std::vector<float>&, int, const ScanGrid<4>&,
                                            ScanStats*, const std::vector<float>*);

}  // namespace ddt::core
