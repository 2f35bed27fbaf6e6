#pragma once
// The check of every integer command-line option: a whole number written in
// decimal (an optional sign, digits only) within [lo, hi], tested on the
// text before CLI11 converts it, so every command answers bad input in the
// same plain words instead of CLI11's "Could not convert", a "not in range"
// for "abc", a 309-digit bound, or a silent wrap:
//   --threads: 'abc' is not a whole number
//   --threads: 99999999 is out of range: give a whole number from 0 to 4096
//   --max-pixels: 0 is out of range: give a positive whole number
//   --max-pixels: 1e30 is not a whole number

#include <CLI/CLI.hpp>

#include <functional>
#include <limits>
#include <string>

CLI::Validator whole_number(long long lo, long long hi = std::numeric_limits<long long>::max());

// A real number (std::stod's reading) that `accept` takes, else
// "must <requirement>, got '<text>'" (CLI11's own checks pass NaN and answer "inf" with a
// 309-digit bound); `description` is the type shown in --help.
CLI::Validator real_number(std::function<bool(double)> accept, const std::string& requirement,
                           const std::string& description);
