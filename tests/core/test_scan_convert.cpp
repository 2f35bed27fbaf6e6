// core::scan_convert<D> for D = 2, 3, 4 from one template: linear fields
// reproduced on every sample (inside and on the clamped rim), input samples
// reproduced bit for bit, one owner per sample, windows equal to the whole.
#include "core/check_mesh.hpp"
#include "core/flips.hpp"
#include "core/grid_delaunay.hpp"
#include "core/lawson.hpp"
#include "core/predicates.hpp"
#include "core/scan_convert.hpp"
#include "core_test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

using namespace ddt;
using namespace ddt::core;
using test::Dim;

namespace {

// Random flips that keep the mesh valid, to leave the Delaunay mesh (long,
// thin and degenerate-tie cells, as an optimized mesh has).
template <int D>
void scramble(SimplexMesh<D>& mesh, int flips, unsigned seed) {
  std::mt19937 rng(seed);
  for (int done = 0, attempt = 0; done < flips && attempt < 50 * flips; ++attempt) {
    const index_t c = std::uniform_int_distribution<index_t>(0, mesh.slot_count() - 1)(rng);
    const unsigned mask = std::uniform_int_distribution<unsigned>(0, (1u << (D + 1)) - 1)(rng);
    if (!mesh.is_live(c) || std::popcount(mask) < 2 || std::popcount(mask) > D) continue;
    FlipPlan<D> plans[4];
    if (propose_flip<D>(mesh, c, mask, plans, 4) == 0) continue;
    apply_flip<D>(mesh, plans[0]);
    ++done;
  }
}

// Two linear functions of the position (channel 0 and 1).
template <int D>
double linear(const Vec<D>& p, int channel) {
  double v = channel == 0 ? 0.3 : -1.2;
  for (int k = 0; k < D; ++k) v += (channel == 0 ? 0.11 - 0.05 * k : 0.02 + 0.07 * k) * p[k];
  return v;
}

template <int D>
std::array<int, D> small_grid() {
  std::array<int, D> n{};
  const int sizes[4] = {5, 4, 6, 3};
  for (int k = 0; k < D; ++k) n[k] = D == 4 ? sizes[k] - 1 : sizes[k];
  return n;
}

template <int D>
ScanGrid<D> scaled(const std::array<int, D>& n, double s) {
  std::array<int, D> out;
  for (int k = 0; k < D; ++k) out[k] = std::max(1, static_cast<int>(std::lround(n[k] * s)));
  return ScanGrid<D>::whole(n, out);
}

// Sample index -> its grid coordinates in the window.
template <int D>
std::array<int, D> unflatten(std::size_t idx, const ScanGrid<D>& g) {
  std::array<int, D> I;
  for (int k = 0; k < D; ++k) I[k] = static_cast<int>(idx % g.size[k]), idx /= g.size[k];
  return I;
}

}  // namespace

TEST_CASE_TEMPLATE("core scan_convert: a linear field (2 channels) is reproduced inside the hull and clamped on the rim",
                   T, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  const std::array<int, D> n = small_grid<D>();
  SimplexMesh<D> mesh = grid_delaunay<D>(n);
  scramble<D>(mesh, D == 4 ? 150 : 300, 3);
  REQUIRE(check_mesh<D>(mesh) == "");
  std::vector<float> values;
  for (const Vec<D>& p : mesh.points)
    for (int c = 0; c < 2; ++c) values.push_back(static_cast<float>(linear<D>(p, c)));
  for (const double s : {1.0, 2.5, 3.0, 4.0}) {
    CAPTURE(s);
    const ScanGrid<D> g = scaled<D>(n, s);
    ScanStats st;
    const std::vector<float> out = scan_convert<D>(mesh, values, 2, g, &st);
    REQUIRE(out.size() == 2 * g.count());
    CHECK(st.uncovered == 0);
    CHECK(st.overcovered == 0);
    CHECK(st.owned + st.rim == static_cast<long long>(g.count()));
    CHECK(st.owned > 0);
    double worst = 0;
    for (std::size_t idx = 0; idx < g.count(); ++idx) {
      const std::array<int, D> I = unflatten<D>(idx, g);
      Vec<D> p;
      for (int k = 0; k < D; ++k) p[k] = std::clamp((I[k] + 0.5) / g.scale[k], 0.5, n[k] - 0.5);
      for (int c = 0; c < 2; ++c) worst = std::max(worst, std::abs(out[2 * idx + c] - linear<D>(p, c)));
    }
    CHECK(worst < 4e-6);
  }
}

// A quadratic function of the position (per channel) and its gradient.
template <int D>
double quadratic(const Vec<D>& p, int channel) {
  double v = linear<D>(p, channel);
  for (int k = 0; k < D; ++k)
    for (int l = k; l < D; ++l) v += (channel == 0 ? 0.013 * (k + 1) - 0.004 * l : -0.009 + 0.006 * (k + l)) * p[k] * p[l];
  return v;
}
template <int D>
double quadratic_slope(const Vec<D>& p, int channel, int axis) {
  const double h = 1e-3;  // central differences are exact for quadratics (to rounding)
  Vec<D> a = p, b = p;
  a[axis] -= h, b[axis] += h;
  return (quadratic<D>(b, channel) - quadratic<D>(a, channel)) / (2 * h);
}

TEST_CASE_TEMPLATE("core scan_convert, cubic: a quadratic field with exact vertex gradients is reproduced inside the hull "
                   "and on the clamped rim, on scrambled meshes",
                   T, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  const std::array<int, D> n = small_grid<D>();
  SimplexMesh<D> mesh = grid_delaunay<D>(n);
  scramble<D>(mesh, D == 4 ? 150 : 300, 7);
  REQUIRE(check_mesh<D>(mesh) == "");
  std::vector<float> values, gradients;
  for (const Vec<D>& p : mesh.points)
    for (int c = 0; c < 2; ++c) {
      values.push_back(static_cast<float>(quadratic<D>(p, c)));
      for (int k = 0; k < D; ++k) gradients.push_back(static_cast<float>(quadratic_slope<D>(p, c, k)));
    }
  for (const double s : {2.5, 4.0}) {
    CAPTURE(s);
    const ScanGrid<D> g = scaled<D>(n, s);
    ScanStats st;
    const std::vector<float> out = scan_convert<D>(mesh, values, 2, g, &st, &gradients);
    const std::vector<float> flat = scan_convert<D>(mesh, values, 2, g);
    CHECK(st.owned + st.rim == static_cast<long long>(g.count()));
    double worst = 0, worst_linear = 0;
    for (std::size_t idx = 0; idx < g.count(); ++idx) {
      const std::array<int, D> I = unflatten<D>(idx, g);
      Vec<D> p;
      for (int k = 0; k < D; ++k) p[k] = std::clamp((I[k] + 0.5) / g.scale[k], 0.5, n[k] - 0.5);
      for (int c = 0; c < 2; ++c) {
        worst = std::max(worst, std::abs(out[2 * idx + c] - quadratic<D>(p, c)));
        worst_linear = std::max(worst_linear, std::abs(flat[2 * idx + c] - quadratic<D>(p, c)));
      }
    }
    CHECK(worst < 2e-5);
    CHECK(worst_linear > 1e-3);  // the linear render cannot: the check above tests the patch
  }
}

TEST_CASE_TEMPLATE("core scan_convert, cubic: input samples are kept and patches meet continuously across facets",
                   T, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  std::array<int, D> n;
  n.fill(5);
  SimplexMesh<D> mesh = grid_delaunay<D>(n);
  scramble<D>(mesh, 200, 11);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> values(mesh.points.size()), gradients(mesh.points.size() * D);
  for (float& v : values) v = u(rng);
  for (float& v : gradients) v = u(rng);
  // x3: output samples on the input samples, which must keep their values.
  const ScanGrid<D> g3 = scaled<D>(n, 3);
  const std::vector<float> out3 = scan_convert<D>(mesh, values, 1, g3, nullptr, &gradients);
  double kept = 0;
  for (std::size_t id = 0; id < mesh.points.size(); ++id) {
    std::size_t idx = 0;
    for (int k = D - 1; k >= 0; --k) idx = idx * g3.size[k] + static_cast<std::size_t>(3 * (mesh.points[id][k] - 0.5) + 1);
    kept = std::max(kept, std::abs(double(out3[idx]) - values[id]));
  }
  CHECK(kept < 1e-6);
  // Continuity: at random points of every interior facet the patches of
  // the two cells sharing it agree (each cell with its own vertex order).
  auto patch_of = [&](index_t c, std::array<double, cubic_controls<D>>& b) {
    std::array<Vec<D>, D + 1> p;
    double z[D + 1], grad[(D + 1) * D];
    for (int i = 0; i <= D; ++i) {
      const index_t v = mesh.vertex(c, i);
      p[i] = mesh.points[v];
      z[i] = values[v];
      for (int k = 0; k < D; ++k) grad[i * D + k] = gradients[v * D + k];
    }
    cubic_patch<D>(p, z, grad, b.data());
  };
  double worst = 0, scale = 0;
  int facets = 0;
  for (index_t c = 0; c < mesh.slot_count(); ++c) {
    if (!mesh.is_live(c)) continue;
    for (int i = 0; i <= D; ++i) {
      const index_t f = mesh.opp[(D + 1) * c + i];
      if (f == no_facet || cell_of<D>(f) < c) continue;
      const index_t d = cell_of<D>(f);
      std::array<double, cubic_controls<D>> bc, bd;
      patch_of(c, bc), patch_of(d, bd);
      for (int trial = 0; trial < 3; ++trial) {
        double wc[D + 1] = {}, wd[D + 1] = {}, sum = 0;
        for (int j = 0; j <= D; ++j)
          if (j != i) wc[j] = std::uniform_real_distribution<double>(0.05, 1.0)(rng), sum += wc[j];
        for (int j = 0; j <= D; ++j) {
          wc[j] /= sum;
          for (int l = 0; l <= D; ++l)
            if (mesh.vertex(d, l) == mesh.vertex(c, j) && j != i) wd[l] = wc[j];
        }
        const double a = eval_cubic<D>(bc.data(), wc), b = eval_cubic<D>(bd.data(), wd);
        worst = std::max(worst, std::abs(a - b));
        scale = std::max(scale, std::abs(a));
      }
      ++facets;
    }
  }
  CHECK(facets >= 40);  // 40 interior edges of a 5 x 5 grid; many more in 3D and 4D
  CHECK(scale > 0.1);
  CHECK(worst < 1e-12);
}

TEST_CASE_TEMPLATE("core scan_convert: input samples are reproduced bit for bit where output samples coincide (x3, x1)",
                   T, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  const std::array<int, D> n = small_grid<D>();
  SimplexMesh<D> mesh = grid_delaunay<D>(n);
  scramble<D>(mesh, 200, 5);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> values(mesh.points.size() * 3);
  for (float& v : values) v = u(rng);
  for (const int s : {1, 3}) {
    const ScanGrid<D> g = scaled<D>(n, s);
    const std::vector<float> out = scan_convert<D>(mesh, values, 3, g);
    int mismatches = 0;
    for (std::size_t id = 0; id < mesh.points.size(); ++id) {
      std::size_t idx = 0;
      for (int k = D - 1; k >= 0; --k) idx = idx * g.size[k] + static_cast<std::size_t>(s * (mesh.points[id][k] - 0.5) + s / 2);
      for (int c = 0; c < 3; ++c) mismatches += out[3 * idx + c] != values[3 * id + c];
    }
    CHECK(mismatches == 0);
  }
}

TEST_CASE_TEMPLATE("core scan_convert: every sample has one owner at awkward scales, and a window equals its part of the whole",
                   T, Dim<2>, Dim<3>, Dim<4>) {
  constexpr int D = T::value;
  std::array<int, D> n = small_grid<D>();
  n[0] = 7;
  SimplexMesh<D> mesh = grid_delaunay<D>(n);
  scramble<D>(mesh, 200, 9);
  std::vector<float> values(mesh.points.size());
  std::mt19937 rng(2);
  for (float& v : values) v = std::uniform_real_distribution<float>(-1, 1)(rng);
  for (const double s : {0.5, 1.7, 2.0, 3.3}) {
    CAPTURE(s);
    const ScanGrid<D> g = scaled<D>(n, s);
    ScanStats st;
    const std::vector<float> whole = scan_convert<D>(mesh, values, 1, g, &st);
    CHECK(st.overcovered == 0);
    CHECK(st.uncovered == 0);
    CHECK(st.owned + st.rim == static_cast<long long>(g.count()));
    // A window of the slowest axis, as a tile renders it.
    ScanGrid<D> w = g;
    w.first[D - 1] = g.size[D - 1] / 3;
    w.size[D - 1] = std::max(1, g.size[D - 1] / 2);
    const std::vector<float> part = scan_convert<D>(mesh, values, 1, w);
    const std::size_t slice = g.count() / g.size[D - 1];
    CHECK(std::equal(part.begin(), part.end(), whole.begin() + w.first[D - 1] * slice));
  }
}

TEST_CASE("core scan_convert: a hull that is not a box, no cells, or values of the wrong size are refused") {
  std::array<Vec<3>, 4> p = test::unit_simplex<3>();
  const SimplexMesh<3> tet = mesh_from_cells<3>({p.begin(), p.end()}, {{0, 1, 2, 3}});
  ScanGrid<3> g = ScanGrid<3>::whole({2, 2, 2}, {4, 4, 4});
  CHECK_THROWS(scan_convert<3>(tet, {0, 0, 0, 0}, 1, g));
  CHECK_THROWS(scan_convert<3>(SimplexMesh<3>{}, {}, 1, g));
  const SimplexMesh<3> cube = grid_delaunay<3>({2, 2, 2});
  CHECK_THROWS(scan_convert<3>(cube, std::vector<float>(7, 0.0f), 1, g));
  CHECK_NOTHROW(scan_convert<3>(cube, std::vector<float>(16, 0.0f), 2, g));
}

TEST_CASE_TEMPLATE("core grid_delaunay + optimize_lawson + scan_convert: the whole 3D and 4D pipeline keeps the samples",
                   T, Dim<3>, Dim<4>) {
  // What a volume (D = 3) or a volume series (D = 4) goes through: the
  // grid's Delaunay mesh, the Lawson procedure on two channels, the scan
  // conversion at x3: every input sample comes back bit for bit and every
  // output sample has one owner.
  constexpr int D = T::value;
  std::array<int, D> n{};
  n.fill(D == 4 ? 4 : 6);
  SimplexMesh<D> mesh = grid_delaunay<D>(n);
  std::vector<float> values(mesh.points.size() * 2);
  for (std::size_t id = 0; id < mesh.points.size(); ++id) {
    double r = 0;
    for (int k = 0; k < D; ++k) r += (mesh.points[id][k] - n[k] / 2.0) * (mesh.points[id][k] - n[k] / 2.0);
    values[2 * id] = r < 2.5 * 2.5 ? 1.0f : 0.0f;  // a ball: edges for the flips
    values[2 * id + 1] = static_cast<float>(0.1 * mesh.points[id][0]);
  }
  const LawsonStats ls = optimize_lawson<D>(mesh, values, 2, find_cost("variance"));
  CHECK(ls.flips.total() > 0);
  CHECK(ls.cost_after < ls.cost_before);
  REQUIRE(check_mesh<D>(mesh) == "");
  std::array<int, D> out;
  for (int k = 0; k < D; ++k) out[k] = 3 * n[k];
  const ScanGrid<D> g = ScanGrid<D>::whole(n, out);
  ScanStats st;
  const std::vector<float> image = scan_convert<D>(mesh, values, 2, g, &st);
  CHECK(st.overcovered == 0);
  CHECK(st.uncovered == 0);
  int mismatches = 0;
  for (std::size_t id = 0; id < mesh.points.size(); ++id) {
    std::size_t idx = 0;
    for (int k = D - 1; k >= 0; --k) idx = idx * g.size[k] + static_cast<std::size_t>(3 * (mesh.points[id][k] - 0.5) + 1);
    for (int c = 0; c < 2; ++c) mismatches += image[2 * idx + c] != values[2 * id + c];
  }
  CHECK(mismatches == 0);
}

// The fill rule read literally: sample q belongs to the cell that contains
// q moved by (e, e^2, ..., e^D), by CGAL's perturbed orientation, for every
// cell and sample (no fast path). At integer and half-integer scales many
// samples lie on facets, and scan_convert takes its integer frame there.
TEST_CASE_TEMPLATE("core scan_convert: owners and values equal the fill rule by exact predicates, samples on facets "
                   "included (integer frame)",
                   T, Dim<2>, Dim<3>) {
  constexpr int D = T::value;
  const std::array<int, D> n = small_grid<D>();
  SimplexMesh<D> mesh = grid_delaunay<D>(n);
  scramble<D>(mesh, 150, 4);
  REQUIRE(check_mesh<D>(mesh) == "");
  std::vector<float> values(mesh.points.size());
  std::mt19937 rng(7);
  for (float& v : values) v = std::uniform_real_distribution<float>(-1, 1)(rng);
  for (const double s : {2.0, 2.5, 4.0}) {
    CAPTURE(s);
    const ScanGrid<D> g = scaled<D>(n, s);
    ScanStats st;
    const std::vector<float> out = scan_convert<D>(mesh, values, 1, g, &st);
    long long owned = 0;
    for (std::size_t idx = 0; idx < g.count(); ++idx) {
      const std::array<int, D> I = unflatten<D>(idx, g);
      Vec<D> q;
      for (int k = 0; k < D; ++k) q[k] = (g.first[k] + I[k] + 0.5) / g.scale[k];
      int owners = 0;
      double expected = 0;
      for (index_t c = 0; c < mesh.slot_count(); ++c) {
        if (!mesh.is_live(c)) continue;
        bool inside = true;
        std::array<double, D + 1> w{};
        for (int i = 0; i <= D && inside; ++i) {
          std::array<Vec<D>, D + 1> pts;
          for (int j = 0, m = 0; j <= D; ++j)
            if (j != i) pts[m++] = mesh.points[mesh.vertex(c, j)];
          pts[D] = q;
          const int o = perturbed_orient<D>(pts);
          inside = ((D - i) % 2 == 0 ? o : -o) > 0;
        }
        if (!inside) continue;
        ++owners;
        // Barycentric weights by plain determinants (Cramer), for the value.
        std::array<Vec<D>, D + 1> cell;
        for (int j = 0; j <= D; ++j) cell[j] = mesh.points[mesh.vertex(c, j)];
        auto volume = [](const std::array<Vec<D>, D + 1>& p) {
          std::array<std::array<double, D>, D> m;
          for (int r = 0; r < D; ++r)
            for (int k = 0; k < D; ++k) m[r][k] = p[r + 1][k] - p[0][k];
          if constexpr (D == 2) return m[0][0] * m[1][1] - m[0][1] * m[1][0];
          else
            return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                   m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        };
        const double total = volume(cell);
        for (int j = 0; j <= D; ++j) {
          std::array<Vec<D>, D + 1> p = cell;
          p[j] = q;
          w[j] = volume(p) / total;
          expected += w[j] * values[mesh.vertex(c, j)];
        }
      }
      REQUIRE(owners <= 1);
      if (owners == 1) {
        ++owned;
        CHECK(out[idx] == doctest::Approx(expected).epsilon(1e-5));
      }
    }
    CHECK(owned == st.owned);
    CHECK(st.overcovered == 0);
    CHECK(st.uncovered == 0);
  }
}
