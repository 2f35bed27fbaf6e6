#include "core/predicates.hpp"
#include "core_test_support.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace ddt;
using namespace ddt::core;
using ddt::core::test::Dim;
using ddt::core::test::unit_simplex;

namespace {

__extension__ typedef __int128 int128;  // GCC's; exact enough for the determinants below

// Exact determinant of integer matrices by Laplace expansion (no
// intermediate exceeds a minor's size, so int128 suffices for the
// magnitudes used below).
int128 exact_det(const std::vector<std::vector<int128>>& m) {
  const std::size_t n = m.size();
  if (n == 1) return m[0][0];
  int128 det = 0;
  for (std::size_t col = 0; col < n; ++col) {
    if (m[0][col] == 0) continue;
    std::vector<std::vector<int128>> minor;
    for (std::size_t r = 1; r < n; ++r) {
      std::vector<int128> row;
      for (std::size_t c = 0; c < n; ++c)
        if (c != col) row.push_back(m[r][c]);
      minor.push_back(row);
    }
    const int128 term = m[0][col] * exact_det(minor);
    det += (col % 2 == 0) ? term : -term;
  }
  return det;
}

// The exact orientation of points whose coordinates are integers times
// `unit` (a power of two).
template <int D>
int exact_orient(const std::array<Vec<D>, D + 1>& p, double unit) {
  std::vector<std::vector<int128>> m(D, std::vector<int128>(D));
  for (int r = 0; r < D; ++r)
    for (int k = 0; k < D; ++k)
      m[r][k] = static_cast<int128>(std::llround(p[r + 1][k] / unit)) - std::llround(p[0][k] / unit);
  const int128 det = exact_det(m);
  return (det > 0) - (det < 0);
}

}  // namespace

TEST_CASE_TEMPLATE("core orient: the unit simplex is positive, a transposition negates, a point on a facet gives 0", T,
                   Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  auto p = unit_simplex<D>();
  CHECK(orient<D>(p) == 1);
  std::swap(p[0], p[D]);
  CHECK(orient<D>(p) == -1);
  std::swap(p[0], p[D]);
  // pD moved onto the hyperplane of p0 .. p(D-1) (coordinate D - 1 set to 0).
  p[D] = Vec<D>{};
  p[D][0] = 0.75;
  CHECK(orient<D>(p) == 0);
}

TEST_CASE_TEMPLATE("core orient: agrees with exact integer arithmetic on nearly degenerate lattice points", T, Dim<2>,
                   Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  // Coordinates: integers below 2^22 times 2^-20, so exact_orient's
  // integers fit. q lies on the line p0 p1, then moves by -1, 0 or +1
  // unit: exactly zero or a cofactor-sized determinant.
  const double unit = std::ldexp(1.0, -20);
  std::mt19937 rng(11 + D);
  std::uniform_int_distribution<long long> coordinate(0, (1 << 22) - 1);
  std::uniform_int_distribution<int> offset(-1, 1);
  int zeros = 0, agree = 0;
  const int trials = 300;
  for (int t = 0; t < trials; ++t) {
    std::array<Vec<D>, D + 1> p;
    for (int i = 0; i < D; ++i)
      for (int k = 0; k < D; ++k) p[i][k] = static_cast<double>(coordinate(rng)) * unit;
    for (int k = 0; k < D; ++k) {
      const double q = 2 * p[1][k] - p[0][k];  // on the line p0 p1, exactly representable
      p[D][k] = q;
    }
    p[D][t % D] += offset(rng) * unit;
    const int expected = exact_orient<D>(p, unit);
    agree += orient<D>(p) == expected;
    zeros += expected == 0;
  }
  CHECK(agree == trials);
  CHECK(zeros > 0);       // the exact zeros were hit
  CHECK(zeros < trials);  // and so were both signs near them
}

TEST_CASE("core orient: Kettner et al.'s classroom example, where the plain double determinant fails") {
  // p = (0.5 + i u, 0.5 + j u), u = 2^-53, against the line (12, 12) (24, 24)
  // ("Classroom examples of robustness problems in geometric
  // computations", 2008): the naive formula gets many signs wrong.
  const double u = std::ldexp(1.0, -53);
  int wrong_naive = 0, wrong_orient = 0;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const std::array<Vec<2>, 3> p = {Vec<2>{0.5 + i * u, 0.5 + j * u}, Vec<2>{12, 12}, Vec<2>{24, 24}};
      const int expected = exact_orient<2>(p, u);
      const double naive = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
      wrong_naive += ((naive > 0) - (naive < 0)) != expected;
      wrong_orient += orient<2>(p) != expected;
    }
  CHECK(wrong_naive > 0);  // the example is hard
  CHECK(wrong_orient == 0);
}

TEST_CASE_TEMPLATE("core in_sphere: inside, on and outside the unit simplex's circumsphere, for either orientation", T,
                   Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  auto p = unit_simplex<D>();
  // Centre (1/2, ..., 1/2), radius sqrt(D)/2: the cube corner (1, ..., 1) is on it.
  Vec<D> centroid, corner, far;
  for (int k = 0; k < D; ++k) centroid[k] = 1.0 / (D + 1), corner[k] = 1, far[k] = 2;
  for (int flipped = 0; flipped < 2; ++flipped) {
    CHECK(in_sphere<D>(p, centroid) == 1);
    CHECK(in_sphere<D>(p, corner) == 0);
    CHECK(in_sphere<D>(p, far) == -1);
    CHECK(in_sphere<D>(p, p[1]) == 0);
    std::swap(p[0], p[1]);
  }
}

TEST_CASE_TEMPLATE(
    "core perturbed_orient: a point on a facet goes to the side of q + (e, e^2, ..., e^D), antisymmetric", T, Dim<2>,
    Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  // Small integer facets; q on the facet (a vertex or an edge midpoint).
  // orient is linear in q, so orient(q + (d, d^2, ..., d^D)) is exactly
  // sum_k c_k d^k with integer cofactors |c_k| < 4096: with d = 2^-12 the
  // first nonzero term decides, as for an infinitesimal e; and q + d^k
  // stays exactly representable.
  const double d = std::ldexp(1.0, -12);
  std::mt19937 rng(5 + D);
  std::uniform_int_distribution<int> coordinate(-4, 4);
  int tested = 0;
  for (int t = 0; t < 400; ++t) {
    std::array<Vec<D>, D + 1> p;
    for (int i = 0; i < D; ++i)
      for (int k = 0; k < D; ++k) p[i][k] = coordinate(rng);
    std::array<Vec<D>, D + 1> facet_only = p;
    facet_only[D] = p[0];
    for (int k = 0; k < D; ++k) facet_only[D][k] += 1e-3 * (k + 1);  // any point: is the facet degenerate?
    for (int k = 0; k < D; ++k) p[D][k] = (t % 2 == 0) ? p[t % D][k] : 0.5 * (p[0][k] + p[1][k]);
    REQUIRE(orient<D>(p) == 0);
    // A facet spanning less than D - 1 dimensions has no side at all.
    bool facet_degenerate = true;
    for (int k = 0; k < D && facet_degenerate; ++k) {
      std::array<Vec<D>, D + 1> probe = p;
      probe[D] = Vec<D>{};
      probe[D][k] = 100;
      if (orient<D>(probe) != 0) facet_degenerate = false;
    }
    if (facet_degenerate) {
      CHECK(perturbed_orient<D>(p) == 0);
      continue;
    }
    std::array<Vec<D>, D + 1> moved = p;
    double power = d;
    for (int k = 0; k < D; ++k, power *= d) moved[D][k] += power;
    const int side = perturbed_orient<D>(p);
    CHECK(side != 0);
    CHECK(side == orient<D>(moved));
    std::swap(p[0], p[1]);
    CHECK(perturbed_orient<D>(p) == -side);
    ++tested;
  }
  CHECK(tested > 300);
}

TEST_CASE("core radon_partition: a convex quadrilateral splits into its diagonals, a point in a triangle 1-3") {
  const std::array<Vec<2>, 4> quad = {Vec<2>{0, 0}, {4, 1}, {5, 5}, {1, 4}};
  const auto s = radon_partition<2>(quad);
  CHECK(s[0] == s[2]);
  CHECK(s[1] == s[3]);
  CHECK(s[0] == -s[1]);
  CHECK(s[0] != 0);
  const std::array<Vec<2>, 4> inner = {Vec<2>{0, 0}, {4, 0}, {1, 1}, {0, 4}};
  const auto t = radon_partition<2>(inner);
  CHECK(t[0] == t[1]);
  CHECK(t[1] == t[3]);
  CHECK(t[2] == -t[0]);
}

TEST_CASE("core radon_partition: a segment through a triangle in 3D is 3-2 - coplanar points give 0 off the circuit") {
  const std::array<Vec<3>, 5> s = {Vec<3>{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {1, 1, 2}, {1, 1, -1}};
  const auto r = radon_partition<3>(s);
  CHECK(r[0] == r[1]);
  CHECK(r[1] == r[2]);
  CHECK(r[3] == r[4]);
  CHECK(r[3] == -r[0]);
  // a, b, c, d coplanar (z = 0) forming a convex quadrilateral, e above:
  // the circuit is the 2D 2-2, e is outside it.
  const std::array<Vec<3>, 5> planar = {Vec<3>{0, 0, 0}, {2, 2, 0}, {2, 0, 0}, {0, 2, 0}, {1, 1, 5}};
  const auto q = radon_partition<3>(planar);
  CHECK(q[4] == 0);
  CHECK(q[0] == q[1]);
  CHECK(q[2] == q[3]);
  CHECK(q[0] == -q[2]);
  CHECK(q[0] != 0);
}

TEST_CASE_TEMPLATE("core radon_partition: both triangulations {S minus a} and {S minus b} have the same content", T,
                   Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  // sum l_i = 0 with |l_i| proportional to the content of S \ s_i: the two
  // sides cover the same polytope, conv S.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int t = 0; t < 50; ++t) {
    std::array<Vec<D>, D + 2> s;
    for (auto& p : s)
      for (double& x : p) x = unit(rng);
    const auto sign = radon_partition<D>(s);
    double side_a = 0, side_b = 0;
    int count_a = 0, count_b = 0;
    for (int i = 0; i < D + 2; ++i) {
      std::array<Vec<D>, D + 1> rest;
      for (int j = 0, n = 0; j < D + 2; ++j)
        if (j != i) rest[n++] = s[j];
      const double content = std::abs(signed_content<D>(rest));
      REQUIRE(sign[i] != 0);
      (sign[i] > 0 ? side_a : side_b) += content;
      (sign[i] > 0 ? count_a : count_b) += 1;
    }
    CHECK(count_a >= 1);
    CHECK(count_b >= 1);
    CHECK(side_a == doctest::Approx(side_b).epsilon(1e-9));
  }
}

TEST_CASE_TEMPLATE("core lattice_exact: orient_lattice equals orient on lattices that satisfy it, degenerate or not", T,
                   Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  // Voxel centres (i + 0.5) up to the largest side the precondition allows
  // in this dimension, and quarter-integers; many exactly degenerate sets.
  const int side = D == 2 ? 1 << 24 : D == 3 ? 1 << 14 : 1 << 10;
  std::mt19937 rng(31 + D);
  for (const double step : {0.5, 0.25}) {
    std::uniform_int_distribution<int> index(0, static_cast<int>(side * 0.5 / step) - 1);
    std::uniform_int_distribution<int> small(0, 3);
    int zeros = 0;
    for (int t = 0; t < 2000; ++t) {
      std::vector<Vec<D>> points(D + 1);
      for (Vec<D>& p : points)
        for (double& c : p) c = (t % 2 ? small(rng) : index(rng)) * step + step;  // small: often degenerate
      std::array<Vec<D>, D + 1> p;
      std::copy(points.begin(), points.end(), p.begin());
      REQUIRE(lattice_exact<D>(points));
      CHECK(orient_lattice<D>(p) == orient<D>(p));
      zeros += orient<D>(p) == 0;
    }
    CHECK(zeros > 0);
  }
}

TEST_CASE_TEMPLATE("core lattice_exact: refuses coordinates off any lattice, too large, or not finite", T, Dim<2>,
                   Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  std::vector<Vec<D>> points(2);
  points[1].fill(0.5);
  CHECK(lattice_exact<D>(points));
  points[1][0] = 0.1;  // not a multiple of any 2^-s with s <= 30
  CHECK_FALSE(lattice_exact<D>(points));
  points[1][0] = std::ldexp(1.0, 60 / D);  // D! (2 x)^D > 2^53
  CHECK_FALSE(lattice_exact<D>(points));
  points[1][0] = INFINITY;
  CHECK_FALSE(lattice_exact<D>(points));
  // Kettner et al.'s classroom points are doubles near 0.5 with 53-bit
  // mantissas: no lattice that keeps the determinant exact.
  std::vector<Vec<D>> fine(2);
  fine[1].fill(0.5 + std::ldexp(1.0, -52));
  CHECK_FALSE(lattice_exact<D>(fine));
}

TEST_CASE_TEMPLATE("core perturbed_tie: what perturbed_orient says for a point on the facet, antisymmetric", T, Dim<2>,
                   Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  std::mt19937 rng(17 + D);
  std::uniform_int_distribution<int> coordinate(-3, 3);
  int tested = 0;
  for (int t = 0; t < 300; ++t) {
    std::array<Vec<D>, D> facet;
    for (Vec<D>& p : facet)
      for (double& c : p) c = coordinate(rng);
    std::array<Vec<D>, D + 1> p;
    std::copy(facet.begin(), facet.end(), p.begin());
    p[D] = facet[t % D];  // on the facet: orient is 0
    REQUIRE(orient<D>(p) == 0);
    CHECK(perturbed_tie<D>(facet) == perturbed_orient<D>(p));
    std::swap(facet[0], facet[1]);
    std::swap(p[0], p[1]);
    CHECK(perturbed_tie<D>(facet) == perturbed_orient<D>(p));
    tested += perturbed_tie<D>(facet) != 0;
  }
  CHECK(tested > 200);
}

TEST_CASE("core perturbed_tie: in 2D, the side of the directed line a point on it is pushed to") {
  // The e term (the x-shift) decides first: +1 when u.y > v.y.
  CHECK(perturbed_tie<2>({Vec<2>{0, 1}, Vec<2>{0, 0}}) == 1);
  CHECK(perturbed_tie<2>({Vec<2>{0, 0}, Vec<2>{0, 1}}) == -1);
  // Horizontal: the e^2 term decides, by the direction along x.
  CHECK(perturbed_tie<2>({Vec<2>{0, 0}, Vec<2>{1, 0}}) == 1);
  CHECK(perturbed_tie<2>({Vec<2>{1, 0}, Vec<2>{0, 0}}) == -1);
  CHECK(perturbed_tie<2>({Vec<2>{2, 2}, Vec<2>{2, 2}}) == 0);  // no line
}

TEST_CASE("core on_lattice: multiples of 2^-bits below the bound, and exact edge functions on them") {
  CHECK(on_lattice(0.5, 10, 32768));
  CHECK(on_lattice(-1234.0 + 3.0 / 1024, 10, 32768));
  CHECK_FALSE(on_lattice(1.0 / 2048, 10, 32768));
  CHECK_FALSE(on_lattice(32768, 10, 32768));
  CHECK_FALSE(on_lattice(0.1, 10, 32768));
  CHECK_FALSE(on_lattice(NAN, 10, 32768));
  CHECK_FALSE(on_lattice(INFINITY, 10, 32768));
  // The rasterizer's claim: with u, v on the 2^-10 lattice below 2^15 and
  // (X, Y) integers below 2^15, (v.x - u.x)(Y - u.y) - (v.y - u.y)(X - u.x)
  // has the exact sign (checked against integer arithmetic).
  std::mt19937 rng(23);
  std::uniform_int_distribution<long long> lattice(-(32760LL << 10), 32760LL << 10);
  std::uniform_int_distribution<int> pixel(-32767, 32767);
  const double unit = std::ldexp(1.0, -10);
  int agree = 0;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    std::array<Vec<2>, 3> p;
    p[0] = {lattice(rng) * unit, lattice(rng) * unit};
    p[1] = {lattice(rng) * unit, lattice(rng) * unit};
    if (t % 2) p[1] = {p[0][0] + (pixel(rng) % 8), p[0][1] + (pixel(rng) % 8)};  // short edges: near ties
    p[2] = {double(pixel(rng)), double(pixel(rng))};
    if (t % 4 == 1) p[2] = {std::round(p[0][0]), std::round(p[0][1])};
    for (const Vec<2>& q : p) REQUIRE((on_lattice(q[0], 10, 32768) && on_lattice(q[1], 10, 32768)));
    const double e = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
    agree += ((e > 0) - (e < 0)) == exact_orient<2>(p, unit);
  }
  CHECK(agree == trials);
}

TEST_CASE("core lattice_exact: any point type through an accessor, as for the 2D mesh's points") {
  struct XY {
    double x, y;
  };
  const auto read = [](const XY& p, int k) { return k == 0 ? p.x : p.y; };
  std::vector<XY> pixels = {{0.5, 0.5}, {1023.5, 767.5}};
  std::vector<Vec<2>> same = {Vec<2>{0.5, 0.5}, Vec<2>{1023.5, 767.5}};
  CHECK(lattice_exact<2>(pixels, read) == lattice_exact<2>(same));
  CHECK(lattice_exact<2>(pixels, read));
  pixels[1].y = 0.3;
  CHECK_FALSE(lattice_exact<2>(pixels, read));
}
