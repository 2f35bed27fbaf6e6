#pragma once
// ddt::core::fill_rule — which samples of a grid a simplex owns, exactly:
// scan_convert.cpp's geometry, apart from its scanning and drawing.
//
// A cell's set-up (CellSetup: facet normals from cofactors, exact on
// lattices; floating-point distances with a tolerance), the side of a facet
// a sample lies on (facet_side: the distance where it is decided beyond
// rounding, else an exact dot product on lattices, else CGAL's orientation
// predicate with the cell's facet), never 0: a sample on a facet belongs
// to the side its perturbation (e, e^2, ..., e^D) points to, so every
// sample has one owner. The integer frame (IntegerFrame, IntegerCell) is
// the fast exact path for grids: sides as integer dot products, tie-break
// included, under the precondition stated at integer_frame.
// Internal to core/scan_convert.cpp (templates on the dimension D).

#include "core/predicates.hpp"
#include "core/scan_convert.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace ddt::core::fill_rule {

// Error-free transformations (Knuth's TwoSum, FMA TwoProduct): true when
// x op y was computed without rounding.
inline bool exact_sum(double x, double y, double sum) {
  const double yv = sum - x, xv = sum - yv;
  return (x - xv) + (y - yv) == 0;
}
inline bool exact_product(double x, double y, double product) { return std::fma(x, y, -product) == 0; }

// det of an N x N matrix by cofactor expansion along row 0, plain double:
// exact when the entries are small integers (lattice points' differences).
template <int N, class T = double>
T cofactor_det(const std::array<std::array<T, N>, N>& m) {
  if constexpr (N == 0) {
    return 1;
  } else if constexpr (N == 1) {
    return m[0][0];
  } else if constexpr (N == 2) {
    return m[0][0] * m[1][1] - m[0][1] * m[1][0];
  } else {
    T det = 0;
    for (int j = 0; j < N; ++j) {
      std::array<std::array<T, N - 1>, N - 1> minor;
      for (int r = 1; r < N; ++r)
        for (int c = 0, n = 0; c < N; ++c)
          if (c != j) minor[r - 1][n++] = m[r][c];
      const T term = m[0][j] * cofactor_det<N - 1, T>(minor);
      det = j % 2 == 0 ? det + term : det - term;
    }
    return det;
  }
}

// The generalized cross product n of D - 1 vectors: n . w = det[v_1; ...;
// v_(D-1); w] for every w (D = 3: v_1 x v_2).
template <int D, class T = double>
std::array<T, D> normal_of(const std::array<std::array<T, D>, D - 1>& v) {
  std::array<T, D> n;
  for (int k = 0; k < D; ++k) {
    std::array<std::array<T, D - 1>, D - 1> minor;
    for (int r = 0; r < D - 1; ++r)
      for (int c = 0, m = 0; c < D; ++c)
        if (c != k) minor[r][m++] = v[r][c];
    const T d = cofactor_det<D - 1, T>(minor);
    n[k] = (D - 1 + k) % 2 == 0 ? d : -d;
  }
  return n;
}

// What scanning one simplex needs: facet i is opposite vertex i, raw[i]
// its inward normal from cofactors (exact on lattices), unit[i] and off[i]
// the floating-point distance unit[i] . q + off[i] (>= 0 inside).
template <int D>
struct CellSetup {
  std::array<Vec<D>, D + 1> p;
  std::array<Vec<D>, D + 1> raw;
  std::array<Vec<D>, D + 1> unit;
  std::array<double, D + 1> off;
  std::array<double, D + 1> den;  // raw[i] . (p_i - p_0), i >= 1
  // The rows run along axis order[0] (the cell's longest, in samples), the
  // levels above them along order[1], ..., order[D - 1]: a long thin cell
  // costs its samples, not the rows across it. Arithmetic stays in axis
  // order whatever the rows' axis, so every sample gets the same bits.
  std::array<int, D> order;
  std::array<double, D + 1> inv_row;  // 1 / unit[i][order[0]], 0 when the facet is parallel to the rows
  Vec<D> lo, hi;                  // bounding box
  const double* patch = nullptr;  // the cubic render: K blocks of cubic_controls<D> values; null: linear
};

// The cofactor normal of facet i (opposite vertex i) of a positive cell,
// pointing towards vertex i; in double or in integers (the integer frame).
// Orientation, from the mesh invariant (cells are positive): with base
// b = (i == 0 ? 1 : 0) and the edges p_j - p_b in increasing j (j != i, b),
// det[edges; p_i - p_b] has the sign (-1)^(D - i) for i >= 1 and (-1)^D for
// i = 0 (a cyclic shift).
template <int D, class T>
std::array<T, D> inward_normal(const std::array<std::array<T, D>, D + 1>& p, int i) {
  const int base = i == 0 ? 1 : 0;
  std::array<std::array<T, D>, D - 1> edges;
  int n = 0;
  for (int j = 0; j <= D; ++j) {
    if (j == i || j == base) continue;
    for (int k = 0; k < D; ++k) edges[n][k] = p[j][k] - p[base][k];
    ++n;
  }
  std::array<T, D> normal = normal_of<D, T>(edges);
  if (((i == 0 ? D : D - i) % 2) != 0)
    for (T& x : normal) x = -x;
  return normal;
}

template <int D>
void setup_cell(CellSetup<D>& s, bool distances = true) {
  for (int i = 0; i <= D; ++i) {
    const int base = i == 0 ? 1 : 0;
    const Vec<D> raw = inward_normal<D, double>(s.p, i);
    s.raw[i] = raw;
    if (i >= 1) {
      s.den[i] = 0;
      for (int k = 0; k < D; ++k) s.den[i] += raw[k] * (s.p[i][k] - s.p[0][k]);
    }
    if (!distances) continue;  // the integer frame (below) needs none
    double len = 0;
    for (double x : raw) len += x * x;
    len = std::sqrt(len);
    s.off[i] = 0;
    for (int k = 0; k < D; ++k) {
      s.unit[i][k] = raw[k] / len;
      s.off[i] -= s.unit[i][k] * s.p[base][k];
    }
    const double along = s.unit[i][s.order[0]];
    s.inv_row[i] = std::abs(along) < 1e-12 ? 0.0 : 1.0 / along;
  }
}

// The integer frame, the exact fast path for grids (volumes at integer and
// half-integer scales). Precondition `integer_frame`: there is an f <= 4
// with every point coordinate times 2^f an integer, and 2 * scale[k] is an
// integer. Then with M_k = 2^(f+1) * scale[k] every vertex coordinate times
// M_k and every sample coordinate times M_k (2^f (2 (first + X) + 1)) is an
// integer, and a facet's side at a sample is an integer dot product: the
// fill rule's sign, tie-break included, without rounding. A cell whose
// scaled extent reaches 2^cell_bits takes the floating-point path (the
// products must stay in 64 bits).
template <int D>
struct IntegerFrame {
  bool valid = false;
  std::array<std::int64_t, D> multiplier{};   // M_k
  std::array<std::int64_t, D> sample_base{};  // scaled coordinate of the window's sample 0
  std::array<std::int64_t, D> sample_step{};  // between consecutive samples: 2^(f+1)
  // |edge| < 2^cell_bits bounds the normals by (D-1)! 2^((D-1) cell_bits)
  // and the sides by D times that times 2^(cell_bits + 1).
  static constexpr int cell_bits = D <= 2 ? 28 : D == 3 ? 18 : 13;
};

template <int D>
IntegerFrame<D> integer_frame(const std::vector<Vec<D>>& points, const ScanGrid<D>& grid) {
  IntegerFrame<D> frame;
  int f = 0;
  for (const Vec<D>& p : points)
    for (double c : p) {
      // Scaled coordinates stay below 2^32 * 2^4 * 2^12 = 2^48: exact in double.
      if (!(std::abs(c) < 0x1p32)) return frame;
      while (std::ldexp(c, f) != std::floor(std::ldexp(c, f)))
        if (++f > 4) return frame;
    }
  for (int k = 0; k < D; ++k) {
    const double twice = 2 * grid.scale[k];
    const double twice_phase = 2 * grid.phase[k];
    if (twice != std::floor(twice) || twice > 4096 || std::abs(grid.first[k]) > (1 << 28) ||
        twice_phase != std::floor(twice_phase) || !(std::abs(twice_phase) <= 4096))
      return frame;
    frame.multiplier[k] = static_cast<std::int64_t>(twice) << f;
    frame.sample_step[k] = std::int64_t(2) << f;
    frame.sample_base[k] = (2 * std::int64_t(grid.first[k]) + static_cast<std::int64_t>(twice_phase)) << f;
  }
  frame.valid = true;
  return frame;
}

// One cell in the integer frame: scaled vertices, and per facet i its
// inward normal and the fill rule's tie-break (the sign of the normal's
// first non-zero component: the side of the perturbed sample).
template <int D>
struct IntegerCell {
  std::array<std::array<std::int64_t, D>, D + 1> v;
  std::array<std::array<std::int64_t, D>, D + 1> normal;
  std::array<int, D + 1> tie;
  std::array<double, D + 1> inv_row_slope;  // 1 / (normal[i][row] * sample_step[row]), 0 when parallel to rows
};

// False when the cell is too large for 64-bit sides (then the float path).
template <int D>
bool integer_cell(const IntegerFrame<D>& frame, const CellSetup<D>& s, IntegerCell<D>& cell) {
  constexpr std::int64_t limit = std::int64_t(1) << IntegerFrame<D>::cell_bits;
  for (int i = 0; i <= D; ++i)
    for (int k = 0; k < D; ++k) cell.v[i][k] = static_cast<std::int64_t>(s.p[i][k] * double(frame.multiplier[k]));
  for (int i = 1; i <= D; ++i)
    for (int k = 0; k < D; ++k)
      if (std::abs(cell.v[i][k] - cell.v[0][k]) >= limit) return false;
  for (int i = 0; i <= D; ++i) {
    const std::array<std::int64_t, D> normal = inward_normal<D, std::int64_t>(cell.v, i);
    cell.normal[i] = normal;
    cell.tie[i] = 0;
    for (int k = 0; k < D && cell.tie[i] == 0; ++k)
      if (normal[k] != 0) cell.tie[i] = normal[k] > 0 ? 1 : -1;
    const int row = s.order[0];
    const std::int64_t slope = normal[row] * frame.sample_step[row];
    cell.inv_row_slope[i] = slope == 0 ? 0.0 : 1.0 / double(slope);
  }
  return true;
}

// The sign of n . (q - a) when every step is exact (then +1, -1 or a true
// 0); false when some step rounded.
template <int D>
[[gnu::always_inline]] inline bool exact_dot_sign(const Vec<D>& n, const Vec<D>& q, const Vec<D>& a, int& sign) {
  double sum = 0;
  for (int k = 0; k < D; ++k) {
    const double d = q[k] - a[k];
    if (!exact_sum(q[k], -a[k], d)) return false;
    const double prod = n[k] * d;
    const double next = sum + prod;
    if (!exact_product(n[k], d, prod) || !exact_sum(sum, prod, next)) return false;
    sum = next;
  }
  sign = sum > 0 ? 1 : sum < 0 ? -1 : 0;
  return true;
}

// facet_side by CGAL's exact predicates: the cell with q in place of
// vertex i, as orient<D> reads it with q moved to the end (D - i
// transpositions).
template <int D>
[[gnu::noinline]] int exact_facet_side(const CellSetup<D>& s, int i, const Vec<D>& q) {
  std::array<Vec<D>, D + 1> pts;
  for (int j = 0, n = 0; j <= D; ++j)
    if (j != i) pts[n++] = s.p[j];
  pts[D] = q;
  const int o = perturbed_orient<D>(pts);
  return (D - i) % 2 == 0 ? o : -o;
}

// Which side of facet i the sample q lies on, never 0 (the perturbation of
// q by (e, e^2, ..., e^D) decides ties): +1 towards vertex i.
template <int D>
[[gnu::always_inline]] inline int facet_side(const CellSetup<D>& s, int i, const Vec<D>& q, double tol, bool lattice) {
  double d = s.off[i];
  for (int k = 0; k < D; ++k) d += s.unit[i][k] * q[k];
  if (d > tol) return 1;
  if (d < -tol) return -1;
  int sign = 0;
  if (lattice && exact_dot_sign<D>(s.raw[i], q, s.p[i == 0 ? 1 : 0], sign)) {
    if (sign != 0) return sign;
    for (int k = 0; k < D; ++k)  // raw[i] is the exact gradient of the side's determinant
      if (s.raw[i][k] != 0) return s.raw[i][k] > 0 ? 1 : -1;
  }
  return exact_facet_side<D>(s, i, q);
}

template <int D>
[[gnu::always_inline]] inline bool inside(const CellSetup<D>& s, const Vec<D>& q, double tol, bool lattice) {
  for (int i = 0; i <= D; ++i)
    if (facet_side<D>(s, i, q, tol, lattice) <= 0) return false;
  return true;
}

}  // namespace ddt::core::fill_rule
