#include "commands.hpp"
#include "whole_number.hpp"

#include "ddtscale/options.hpp"
#include "image/annealing.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>

void add_optimizer_options(CLI::App& app, std::string& optimizer, ddt::AnnealOptions& anneal) {
  app.add_option("--optimizer", optimizer,
                 "lawson (generalized Lawson: only cost-lowering flips), anneal (simulated annealing over the "
                 "same flips, then a Lawson pass) or lookahead (Lawson, plus pairs of flips that lower the cost "
                 "only together)")
      ->check(CLI::IsMember(ddt::optimizer_names()))
      ->capture_default_str();
  const CLI::Validator non_negative = real_number([](double v) { return v >= 0 && std::isfinite(v); },
                                                  "be a finite number >= 0", "FLOAT >= 0");
  app.add_option("--seed", anneal.seed, "anneal: seed of the random moves (same seed, same result)")
      ->check(whole_number(0))
      ->capture_default_str();
  app.add_option("--anneal-t0", anneal.initial_temperature,
                 "anneal: initial temperature in cost units; 0 = automatic (see --anneal-accept)")
      ->check(non_negative)
      ->capture_default_str();
  app.add_option("--anneal-accept", anneal.initial_acceptance,
                 "anneal: automatic T0 accepts the mean uphill flip with this probability")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  // Strictly inside (0, 1): T must fall, and never to 0.
  const CLI::Validator open_unit_interval =
      real_number([](double v) { return v > 0 && v < 1; }, "lie strictly between 0 and 1", "FLOAT in (0, 1)");
  app.add_option("--anneal-cooling", anneal.cooling, "anneal: T is multiplied by this after each step")
      ->check(open_unit_interval)
      ->capture_default_str();
  app.add_option("--anneal-steps", anneal.temperature_steps, "anneal: number of temperature steps")
      ->check(whole_number(0, std::numeric_limits<int>::max()))
      ->capture_default_str();
  app.add_option("--anneal-moves", anneal.moves_per_edge,
                 "anneal: random flip proposals per interior edge at each temperature")
      ->check(non_negative)
      ->capture_default_str();
}
