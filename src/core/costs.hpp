#pragma once
// Cost functions of data-dependent triangulation, as pure functions of
// vertex positions and values (never of a mesh). Dimension-independent:
// an n-simplex has n+1 vertices and n+1 facets; in 2D the simplex is a
// triangle and a facet an edge, in 3D a tetrahedron and a triangle.
//
// Source: Z. Tóth, I. Viola, A. Ferko, M. E. Gröller, "N-dimensional
// Data-Dependent Reconstruction Using Topological Changes", Sect. 3.
// The optimized quantity is the weighted content
//     cost(K) = sum over n-simplices s of content(s) * w(s)
// with either
//   variance:   w(s) = Var(z_1 .. z_{n+1})                  (C0 weight)
//   sederberg:  w(s) = mean over the n+1 facets f of c(f)   (near-C1 weight)
//               c(f) = |grad P1| |grad P2| - grad P1 . grad P2
//               P1, P2 the linear interpolants on the two simplices sharing
//               f; c(f) = 0 on the hull (Yu, Morse, Sederberg 2001, eq. for
//               the 2D edge cost; generalized in the paper).
// and the classic 2D DDT sum over facets (Dyn, Levin, Rippa 1990):
//   sederberg-edge: cost(K) = sum over interior facets of c(f).
// The classic facet costs of N. Dyn, D. Levin, S. Rippa, "Data dependent
// triangulations for piecewise linear interpolation", IMA J. Numer. Anal.
// 10 (1990) 137-154 (DLR), generalized to facets as the paper does for
// Sederberg's (formulas at each function below), each in both forms:
//   abn, abn-edge   angle between the normals of the two graphs
//   jnd, jnd-edge   jump of the normal derivative across the facet
//   dlp, dlp-edge   deviation of each plane from the other simplex's apex value
//   dp,  dp-edge    the same, measured perpendicular to the planes
// They vanish when the two simplices lie in one plane, as Sederberg's does.
// For the weighted-content form with a facet cost, the total rewrites as
//   sum over interior facets f of c(f) * (content(s1) + content(s2)) / (n+1),
// which is how the optimizer evaluates it.
//
// Multi-channel data: the cost of a configuration is the sum of the
// per-channel costs (callers pass luminance as a single channel instead
// when asked to).

#include <Eigen/Dense>

#include <array>
#include <string>
#include <vector>

namespace ddt {

// The most value channels a cost is evaluated on (RGBA and a few more).
inline constexpr int max_cost_channels = 8;

enum class CostForm {
  simplex_weight,          // sum_s content(s) * w(s), w from s's own values
  facet_weighted_content,  // sum_s content(s) * mean_{f in s} c(f)
  facet_sum,               // sum over interior facets of c(f)
};

// What a facet cost sees of a facet shared by simplices s1 and s2, for one
// channel, in any dimension `dim` (2: an edge between triangles, 3: a
// triangle between tetrahedra). Pointers address `dim` coordinates.
struct FacetPair {
  int dim = 2;
  const double* g1 = nullptr;      // gradient of the linear interpolant on s1
  const double* g2 = nullptr;      // ... on s2
  const double* normal = nullptr;  // unit normal of the facet, pointing from s1 into s2
  const double* base = nullptr;    // one vertex of the facet
  double z_base = 0;               // its value
  const double* apex1 = nullptr;   // the vertex of s1 off the facet
  const double* apex2 = nullptr;   // the vertex of s2 off the facet
  double z_apex1 = 0, z_apex2 = 0; // their values
};

struct CostFunction {
  const char* name;
  const char* summary;
  CostForm form;
  // simplex_weight form: weight from the values at the n+1 vertices.
  double (*simplex_weight)(const double* values, int count) = nullptr;
  // facet forms: cost of one facet for one channel.
  double (*facet_cost)(const FacetPair& facet) = nullptr;
  // Whether facet_cost reads more than g1 and g2 (normal, base, apexes);
  // the optimizer skips computing them otherwise.
  bool facet_geometry = false;
};

// Population variance of count values (the paper's variance weight).
double variance_weight(const double* values, int count);

// Sederberg's cost: |g1| |g2| - g1 . g2 (>= 0; 0 when the gradients are parallel
// and point the same way, in particular when the two planes coincide).
double sederberg_cost(const double* g1, const double* g2, int dim);
double sederberg_facet_cost(const FacetPair& facet);  // the same, as a facet cost

// The classic costs of Dyn, Levin and Rippa (1990) for one facet and one
// channel, in any dimension (see costs.cpp for each formula and its source).
// Values are compared with distances as stored (pixel units), so abn and dp
// depend on the value scale; jnd and dlp scale linearly with it.
double abn_facet_cost(const FacetPair& facet);  // radians, in [0, pi)
double jnd_facet_cost(const FacetPair& facet);  // reads normal
double dlp_facet_cost(const FacetPair& facet);  // reads base, apex1, apex2
double dp_facet_cost(const FacetPair& facet);   // reads base, apex1, apex2

// Every cost the optimizer knows, in the order `--help` lists them.
const std::vector<CostFunction>& cost_functions();
// Throws ddt::Error naming the valid costs when `name` is unknown.
const CostFunction& find_cost(const std::string& name);
std::string cost_names_joined();  // "sederberg, variance, ..."

// Gradient of the linear function taking values z_i at the N+1 vertices p_i
// of a non-degenerate N-simplex. Solves (p_i - p_0) . g = z_i - z_0.
template <int N>
Eigen::Matrix<double, N, 1> simplex_gradient(const std::array<Eigen::Matrix<double, N, 1>, N + 1>& p,
                                             const std::array<double, N + 1>& z) {
  Eigen::Matrix<double, N, N> edges;
  Eigen::Matrix<double, N, 1> rise;
  for (int i = 0; i < N; ++i) {
    edges.row(i) = (p[i + 1] - p[0]).transpose();
    rise(i) = z[i + 1] - z[0];
  }
  return edges.partialPivLu().solve(rise);
}

// Content (length, area, volume, ...) of an N-simplex: |det(p_i - p_0)| / N!.
template <int N>
double simplex_content(const std::array<Eigen::Matrix<double, N, 1>, N + 1>& p) {
  Eigen::Matrix<double, N, N> edges;
  for (int i = 0; i < N; ++i) edges.col(i) = p[i + 1] - p[0];
  double factorial = 1;
  for (int i = 2; i <= N; ++i) factorial *= i;
  return std::abs(edges.determinant()) / factorial;
}

}  // namespace ddt
