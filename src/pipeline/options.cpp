#include "ddtscale/options.hpp"

#include "util/error.hpp"
#include "util/text.hpp"

#include <array>
#include <utility>

namespace ddt {
namespace {

// The value of `name` in `table`, or a ddt::Error naming what was asked
// for and listing the valid names in `order`.
template <class Enum, std::size_t N>
Enum by_name(const std::array<std::pair<const char*, Enum>, N>& table, const std::string& name, const char* what,
             const std::vector<std::string>& order) {
  for (const auto& [n, value] : table)
    if (name == n) return value;
  throw Error("unknown " + std::string(what) + " '" + name + "' (valid: " + joined(order) + ")");
}

template <class Enum, std::size_t N>
const char* name_of(const std::array<std::pair<const char*, Enum>, N>& table, Enum value) {
  for (const auto& [n, v] : table)
    if (v == value) return n;
  return "?";
}

constexpr std::array<std::pair<const char*, Optimizer>, 3> optimizers{
    {{"lawson", Optimizer::lawson}, {"anneal", Optimizer::anneal}, {"lookahead", Optimizer::lookahead}}};
constexpr std::array<std::pair<const char*, Render>, 2> renders{{{"cubic", Render::cubic}, {"linear", Render::linear}}};
constexpr std::array<std::pair<const char*, SlopeLimiter>, 4> limiters{{{"mc4", SlopeLimiter::mc4},
                                                                         {"mc", SlopeLimiter::mc},
                                                                         {"central", SlopeLimiter::central},
                                                                         {"minmod", SlopeLimiter::minmod}}};

template <class Enum, std::size_t N>
std::vector<std::string> names_of(const std::array<std::pair<const char*, Enum>, N>& table) {
  std::vector<std::string> names;
  for (const auto& entry : table) names.emplace_back(entry.first);
  return names;
}

}  // namespace

const std::vector<std::string>& optimizer_names() {
  static const std::vector<std::string> names = names_of(optimizers);
  return names;
}
Optimizer optimizer_by_name(const std::string& name) { return by_name(optimizers, name, "optimizer", optimizer_names()); }
const char* to_string(Optimizer optimizer) { return name_of(optimizers, optimizer); }

const std::vector<std::string>& render_names() {
  static const std::vector<std::string> names = names_of(renders);
  return names;
}
Render render_by_name(const std::string& name) { return by_name(renders, name, "render mode", render_names()); }
const char* to_string(Render render) { return name_of(renders, render); }

const std::vector<std::string>& slope_limiter_names() {
  static const std::vector<std::string> names = names_of(limiters);
  return names;
}
SlopeLimiter slope_limiter_by_name(const std::string& name) {
  // The message's order is the one it always had.
  static const std::vector<std::string> alphabetical = {"central", "mc", "mc4", "minmod"};
  return by_name(limiters, name, "slope limiter", alphabetical);
}
const char* to_string(SlopeLimiter limiter) { return name_of(limiters, limiter); }

}  // namespace ddt
