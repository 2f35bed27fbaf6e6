#include "core/costs.hpp"

#include "util/error.hpp"

#include <cmath>

namespace ddt {

double variance_weight(const double* values, int count) {
  double mean = 0;
  for (int i = 0; i < count; ++i) mean += values[i];
  mean /= count;
  double var = 0;
  for (int i = 0; i < count; ++i) var += (values[i] - mean) * (values[i] - mean);
  return var / count;
}

double sederberg_cost(const double* g1, const double* g2, int dim) {
  double n1 = 0, n2 = 0, dot = 0;
  for (int i = 0; i < dim; ++i) {
    n1 += g1[i] * g1[i];
    n2 += g2[i] * g2[i];
    dot += g1[i] * g2[i];
  }
  // Clamp: rounding can make the product of norms fall a hair below the dot.
  return std::max(0.0, std::sqrt(n1 * n2) - dot);
}

double sederberg_facet_cost(const FacetPair& facet) { return sederberg_cost(facet.g1, facet.g2, facet.dim); }

// ABN, "angle between normals" (DLR 1990): the angle between the
// normals of the graphs of P1 and P2, n_i = (-grad P_i, 1) in R^(dim+1):
//     cos(theta) = (1 + g1 . g2) / sqrt((1 + |g1|^2) (1 + |g2|^2)).
// Evaluated as theta = atan2(|n1 ^ n2|, n1 . n2), accurate for small angles,
// with |n1 ^ n2|^2 the sum of the squared 2x2 minors of (n1, n2) (Lagrange's
// identity): sum_{i<j} (g1_i g2_j - g1_j g2_i)^2 + sum_i (g1_i - g2_i)^2.
double abn_facet_cost(const FacetPair& facet) {
  const double *g1 = facet.g1, *g2 = facet.g2;
  double wedge2 = 0, dot = 1;
  for (int i = 0; i < facet.dim; ++i) {
    dot += g1[i] * g2[i];
    wedge2 += (g1[i] - g2[i]) * (g1[i] - g2[i]);
    for (int j = i + 1; j < facet.dim; ++j) {
      const double m = g1[i] * g2[j] - g1[j] * g2[i];
      wedge2 += m * m;
    }
  }
  return std::atan2(std::sqrt(wedge2), dot);
}

// JND, "jump in normal derivatives" (DLR 1990): the jump of the
// derivative across the facet, along its unit normal n:
//     c(f) = |n . (grad P1 - grad P2)|.
// P1 and P2 agree on the facet, so grad P1 - grad P2 is parallel to n and
// c(f) = |grad P1 - grad P2| in exact arithmetic; the projection on n is
// DLR's form.
double jnd_facet_cost(const FacetPair& facet) {
  double jump = 0;
  for (int i = 0; i < facet.dim; ++i) jump += facet.normal[i] * (facet.g1[i] - facet.g2[i]);
  return std::abs(jump);
}

namespace {

// How far each simplex's plane misses the value at the other simplex's apex:
//   d1 = P1(apex2) - z_apex2,  d2 = P2(apex1) - z_apex1,
// with P_i(x) = z_base + g_i . (x - base) (both planes pass through the facet).
void plane_deviations(const FacetPair& facet, double& d1, double& d2) {
  double p1 = facet.z_base, p2 = facet.z_base;
  for (int i = 0; i < facet.dim; ++i) {
    p1 += facet.g1[i] * (facet.apex2[i] - facet.base[i]);
    p2 += facet.g2[i] * (facet.apex1[i] - facet.base[i]);
  }
  d1 = p1 - facet.z_apex2;
  d2 = p2 - facet.z_apex1;
}

double squared_norm(const double* g, int dim) {
  double s = 0;
  for (int i = 0; i < dim; ++i) s += g[i] * g[i];
  return s;
}

}  // namespace

// DLP, "deviations from linear polynomials" (DLR 1990): the
// vertical deviation of each triangle's plane from the data at the vertex
// of the other triangle, d1 and d2 above, combined in the Euclidean norm
//     c(f) = sqrt(d1^2 + d2^2)
// (the combining norm is our choice). Since P2 - P1 vanishes on the facet,
// |d1| = h2 |n . (g1 - g2)| and |d2| = h1 |n . (g1 - g2)| with h_i the
// distance of apex i from the facet: the jump of JND weighted by the
// apexes' distances.
double dlp_facet_cost(const FacetPair& facet) {
  double d1, d2;
  plane_deviations(facet, d1, d2);
  return std::sqrt(d1 * d1 + d2 * d2);
}

// DP, "distances from planes" (DLR 1990): as DLP, but each
// deviation measured perpendicular to the plane, i.e. the Euclidean
// distance in R^(dim+1) from the apex's data point to the other graph:
//     c(f) = sqrt(d1^2 / (1 + |g1|^2) + d2^2 / (1 + |g2|^2)).
double dp_facet_cost(const FacetPair& facet) {
  double d1, d2;
  plane_deviations(facet, d1, d2);
  return std::sqrt(d1 * d1 / (1 + squared_norm(facet.g1, facet.dim)) +
                   d2 * d2 / (1 + squared_norm(facet.g2, facet.dim)));
}

const std::vector<CostFunction>& cost_functions() {
  static const std::vector<CostFunction> table = {
      {"sederberg", "weighted content, w = mean Sederberg cost of the simplex's facets (paper's default)",
       CostForm::facet_weighted_content, nullptr, &sederberg_facet_cost},
      {"variance", "weighted content, w = variance of the vertex values (paper's C0 weight)",
       CostForm::simplex_weight, &variance_weight, nullptr},
      {"sederberg-edge", "classic 2D DDT: sum of Sederberg costs over interior edges",
       CostForm::facet_sum, nullptr, &sederberg_facet_cost},
      {"abn", "weighted content, w = mean angle between the normals across the simplex's facets (DLR ABN)",
       CostForm::facet_weighted_content, nullptr, &abn_facet_cost},
      {"jnd", "weighted content, w = mean jump in normal derivative across the simplex's facets (DLR JND)",
       CostForm::facet_weighted_content, nullptr, &jnd_facet_cost, true},
      {"dlp", "weighted content, w = mean deviation from the neighbours' planes (DLR DLP)",
       CostForm::facet_weighted_content, nullptr, &dlp_facet_cost, true},
      {"dp", "weighted content, w = mean distance from the neighbours' planes (DLR DP)",
       CostForm::facet_weighted_content, nullptr, &dp_facet_cost, true},
      {"abn-edge", "classic 2D DDT: sum over interior edges of the angle between normals (DLR ABN)",
       CostForm::facet_sum, nullptr, &abn_facet_cost},
      {"jnd-edge", "classic 2D DDT: sum over interior edges of the jump in normal derivatives (DLR JND)",
       CostForm::facet_sum, nullptr, &jnd_facet_cost, true},
      {"dlp-edge", "classic 2D DDT: sum over interior edges of the deviations from linear polynomials (DLR DLP)",
       CostForm::facet_sum, nullptr, &dlp_facet_cost, true},
      {"dp-edge", "classic 2D DDT: sum over interior edges of the distances from planes (DLR DP)",
       CostForm::facet_sum, nullptr, &dp_facet_cost, true},
  };
  return table;
}

std::string cost_names_joined() {
  std::string names;
  for (const auto& c : cost_functions()) names += (names.empty() ? "" : ", ") + std::string(c.name);
  return names;
}

const CostFunction& find_cost(const std::string& name) {
  for (const auto& c : cost_functions())
    if (name == c.name) return c;
  throw Error("unknown cost '" + name + "' (valid: " + cost_names_joined() + ")");
}

}  // namespace ddt
