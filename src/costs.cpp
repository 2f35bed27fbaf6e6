#include "costs.hpp"

#include "error.hpp"

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

const std::vector<CostFunction>& cost_functions() {
  static const std::vector<CostFunction> table = {
      {"sederberg", "weighted content, w = mean Sederberg cost of the simplex's facets (paper's default)",
       CostForm::facet_weighted_content, nullptr, &sederberg_facet_cost},
      {"variance", "weighted content, w = variance of the vertex values (paper's C0 weight)",
       CostForm::simplex_weight, &variance_weight, nullptr},
      {"sederberg-edge", "classic 2D DDT: sum of Sederberg costs over interior edges",
       CostForm::facet_sum, nullptr, &sederberg_facet_cost},
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
