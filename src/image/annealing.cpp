#include "image/annealing.hpp"

#include "util/error.hpp"

#include <cmath>
#include <random>

namespace ddt {
namespace {

// Uniform draws from the fully specified mt19937_64 output, without the
// implementation-defined std:: distributions, so runs reproduce anywhere.
struct Random {
  std::mt19937_64 engine;
  explicit Random(std::uint64_t seed) : engine(seed) {}
  double unit() { return static_cast<double>(engine() >> 11) * 0x1.0p-53; }  // [0, 1)
  index_t below(index_t n) { return static_cast<index_t>(engine() % static_cast<std::uint64_t>(n)); }
};

// A half-edge slot drawn uniformly among the interior ones: each interior
// edge owns two slots, so edges are drawn uniformly too. Flips move edges
// between slots, so hull slots are redrawn rather than listed once.
index_t random_interior_half_edge(const Mesh2& mesh, Random& rng) {
  for (;;) {
    const index_t h = rng.below(mesh.half_edge_count());
    if (mesh.opp[h] != no_edge) return h;
  }
}

long long interior_edge_count(const Mesh2& mesh) {
  long long n = 0;
  for (index_t e = 0; e < mesh.half_edge_count(); ++e) n += mesh.opp[e] != no_edge;
  return n / 2;
}

void check_channels(int K) {
  if (K < 1 || K > max_cost_channels)
    throw Error("the cost takes 1 to " + std::to_string(max_cost_channels) + " channels, got " + std::to_string(K));
}

}  // namespace

void check_anneal_options(const AnnealOptions& o) {
  if (!(o.initial_acceptance > 0 && o.initial_acceptance < 1))
    throw Error("the initial acceptance of annealing must lie strictly between 0 and 1");
  if (!(o.cooling > 0 && o.cooling < 1)) throw Error("the cooling factor of annealing must lie strictly between 0 and 1");
  if (o.temperature_steps < 0) throw Error("the number of annealing temperature steps must be >= 0");
  if (!(o.moves_per_edge >= 0) || !std::isfinite(o.moves_per_edge))
    throw Error("the annealing moves per edge must be a number >= 0");
  if (!std::isfinite(o.initial_temperature)) throw Error("the initial annealing temperature must be finite");
}

double initial_temperature(const Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                           double acceptance, std::uint64_t seed, int samples) {
  check_channels(K);
  if (interior_edge_count(mesh) == 0) return 0;
  Random rng(seed ^ 0x9e3779b97f4a7c15ULL);  // a stream of its own
  double sum = 0;
  long long uphill = 0;
  for (int i = 0; i < samples; ++i) {
    const index_t e = random_interior_half_edge(mesh, rng);
    if (!is_flippable(mesh, e)) continue;
    const double delta = -flip_costs(mesh, values, K, cost, e).gain();
    if (delta > 0) sum += delta, ++uphill;
  }
  return uphill == 0 ? 0.0 : sum / uphill / -std::log(acceptance);
}

AnnealStats optimize_anneal(Mesh2& mesh, const std::vector<float>& values, int K, const CostFunction& cost,
                            const AnnealOptions& options, const LawsonOptions& lawson) {
  check_channels(K);
  check_anneal_options(options);
  AnnealStats stats;
  stats.cost_before = total_cost(mesh, values, K, cost);
  double cost_now = stats.cost_before;
  const long long edges = interior_edge_count(mesh);

  double T = options.initial_temperature > 0
                 ? options.initial_temperature
                 : initial_temperature(mesh, values, K, cost, options.initial_acceptance, options.seed);
  stats.initial_temperature = T;
  Random rng(options.seed);
  const long long moves = edges == 0 ? 0 : std::llround(options.moves_per_edge * static_cast<double>(edges));

  for (int step = 0; step < options.temperature_steps && moves > 0; ++step) {
    long long accepted_now = 0;
    for (long long m = 0; m < moves; ++m) {
      const index_t e = random_interior_half_edge(mesh, rng);
      ++stats.proposals;
      if (!is_flippable(mesh, e)) continue;
      ++stats.flippable;
      const double delta = -flip_costs(mesh, values, K, cost, e).gain();
      // Metropolis: downhill and neutral flips always; uphill ones with
      // probability exp(-delta / T) (never at T = 0).
      const bool accept = delta <= 0 || (T > 0 && rng.unit() < std::exp(-delta / T));
      if (!accept) continue;
      flip_edge(mesh, e);
      cost_now += delta;
      ++accepted_now;
      if (delta > 0) ++stats.uphill;
    }
    stats.accepted += accepted_now;
    ++stats.temperature_steps;
    stats.final_temperature = T;
    if (options.on_step) options.on_step(step + 1, T, accepted_now, cost_now);
    T *= options.cooling;
  }
  stats.cost_annealed = total_cost(mesh, values, K, cost);
  stats.cost_after = stats.cost_annealed;
  if (options.final_lawson) {
    stats.lawson = optimize_lawson(mesh, values, K, cost, lawson);
    stats.cost_after = stats.lawson.cost_after;
  }
  return stats;
}

}  // namespace ddt
