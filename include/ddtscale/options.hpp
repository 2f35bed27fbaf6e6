#pragma once
// The choices among the library's options, typed. Each is parsed once
// from its name where a user gives it (the command line, the Python
// module, `ddtscale eval`'s method names) by *_by_name, which throws
// ddt::Error with a one-line message listing the valid names, and named
// back by to_string (for --help defaults, logs and the Python defaults).

#include <string>
#include <vector>

namespace ddt {

// The mesh optimizer (image/optimizer_choice.hpp): the generalized Lawson
// procedure, simulated annealing then Lawson, or Lawson with two-flip moves.
enum class Optimizer { lawson, anneal, lookahead };

// The surface drawn on the mesh: cubic Bézier patches from slope-limited
// vertex gradients (image/cubic_surface.hpp), or the paper's
// piecewise-linear surface.
enum class Render { cubic, linear };

// The slope limiter of the cubic render's vertex gradients
// (image/cubic_surface.hpp).
enum class SlopeLimiter { central, mc, mc4, minmod };

const std::vector<std::string>& optimizer_names();  // lawson, anneal, lookahead
Optimizer optimizer_by_name(const std::string& name);
const char* to_string(Optimizer optimizer);

const std::vector<std::string>& render_names();  // cubic, linear
Render render_by_name(const std::string& name);
const char* to_string(Render render);

const std::vector<std::string>& slope_limiter_names();  // mc4, mc, central, minmod
SlopeLimiter slope_limiter_by_name(const std::string& name);
const char* to_string(SlopeLimiter limiter);

}  // namespace ddt
