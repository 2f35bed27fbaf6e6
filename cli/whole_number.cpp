#include "whole_number.hpp"

#include <charconv>
#include <exception>
#include <string>
#include <system_error>
#include <utility>

CLI::Validator whole_number(long long lo, long long hi) {
  const bool unbounded = hi == std::numeric_limits<long long>::max();
  std::string wanted = lo == 1 ? "a positive whole number" : "a whole number";
  if (!unbounded) wanted += lo == 1 ? " up to " + std::to_string(hi) : " from " + std::to_string(lo) + " to " + std::to_string(hi);
  else if (lo != 1) wanted += " of at least " + std::to_string(lo);
  return CLI::Validator(
      [lo, hi, unbounded, wanted](std::string& text) -> std::string {
        const char* begin = text.data() + (!text.empty() && text.front() == '+' ? 1 : 0);
        const char* end = text.data() + text.size();
        long long value = 0;
        const auto [stop, error] = std::from_chars(begin, end, value);
        const bool digits =
            begin != end && stop == end && (error == std::errc() || error == std::errc::result_out_of_range);
        if (!digits) return "'" + text + "' is not a whole number";
        if (unbounded && (error != std::errc() || value > hi))
          return text + " is too large (at most " + std::to_string(hi) + ")";
        if (error != std::errc() || value < lo || value > hi) return text + " is out of range: give " + wanted;
        return std::string();
      },
      unbounded ? "INT >= " + std::to_string(lo) : "INT in " + std::to_string(lo) + ".." + std::to_string(hi));
}

CLI::Validator real_number(std::function<bool(double)> accept, const std::string& requirement,
                           const std::string& description) {
  return CLI::Validator(
      [accept = std::move(accept), requirement](std::string& text) -> std::string {
        double value = 0;
        try {
          value = std::stod(text);
        } catch (const std::exception&) {
          return "'" + text + "' is not a number";
        }
        return accept(value) ? std::string() : "must " + requirement + ", got '" + text + "'";
      },
      description);
}
