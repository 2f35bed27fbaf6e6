#pragma once
// ddt::grid_points — scattered samples to a regular grid by data-dependent
// triangulation: Delaunay triangulation of the points, generalized Lawson
// optimization of a DDT cost, rendering of the piecewise-linear surface on
// the grid, no-data outside the points' convex hull.
//
// Grid convention (north-up, GDAL's "pixel is area"): the grid covers the
// bounds [xmin, xmax] x [ymin, ymax] with W x H cells; row 0 is the top
// (ymax). Pixel (i, j), column i and row j, holds the surface's value at its
// centre
//     x = xmin + (i + 0.5) * (xmax - xmin) / W
//     y = ymax - (j + 0.5) * (ymax - ymin) / H.
// This is the geotransform (xmin, dx, 0, ymax, 0, -dy) that `gdal_grid
// -txe xmin xmax -tye ymin ymax -outsize W H` writes, so both tools sample the
// same positions. Internally the points are mirrored (y -> -y, exact) before
// triangulating, because the rasterizer's rows run toward increasing y.
//
// No-data: a pixel whose centre lies outside the convex hull of the points
// takes `nodata` in every channel. Centres within `hull_tolerance` pixels
// of the hull (e.g. exactly on it, or off it by the rounding of coordinates
// printed to a text file) count as inside and take the value of the nearest
// hull point. With `alpha`, a last channel is added: 1 inside, 0 outside.
//
// Multi-channel values: one mesh for all channels. The flips are driven by
// the sum of the per-channel costs, by the luminance of the first three
// channels, or by one channel (GridOptions::cost_channel).
//
// Errors: throws ddt::Error (bad size or bounds, fewer than three points
// not on one line, unknown cost, too many channels for the cost).

#include "ddtscale/options.hpp"
#include "image/annealing.hpp"
#include "util/image.hpp"
#include "image/mesh.hpp"
#include "pipeline/stages.hpp"

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace ddt {

struct GridBounds {
  double xmin = 0, ymin = 0, xmax = 0, ymax = 0;
};

struct GridOptions {
  int width = 0, height = 0;            // grid size in pixels (>= 1 each)
  std::optional<GridBounds> bounds;     // default: the points' bounding box
  // A name from costs.hpp. The default differs from the image upscaler's:
  // on scattered samples the classic edge sum of the jumps in normal
  // derivative (Dyn, Levin, Rippa 1990) beat plain Delaunay on steps, ridges
  // and smooth fields alike, where sederberg and variance lose on smooth
  // ones (docs/scattered.md, "Which cost").
  std::string cost = "jnd-edge";
  // What drives the flips: -1 the sum of all channels' costs, -2 the
  // luminance of channels 0, 1, 2 (Rec. 601), k >= 0 channel k alone.
  int cost_channel = -1;
  bool optimize = true;                 // false: render the Delaunay mesh
  Optimizer optimizer = Optimizer::lawson;  // lawson, anneal or lookahead (optimizer_choice.hpp)
  AnnealOptions anneal;                 // the schedule and seed of anneal
  double relative_tolerance = 1e-9;     // a flip must lower the local cost by more than this fraction
  int max_iterations = 10000;
  float nodata = std::numeric_limits<float>::quiet_NaN();
  bool alpha = false;                   // append a coverage channel (1 inside, 0 outside)
  double hull_tolerance = 1e-3;         // pixels; see above
  std::function<void(const std::string&)> log;  // verbose lines; may be empty
};

inline constexpr int cost_channel_sum = -1;
inline constexpr int cost_channel_luma = -2;

// The stage seconds and the optimizer's summary (pipeline/stages.hpp), and
// what is the gridding's own.
struct GridStats : StageSeconds, OptimizerSummary<long long> {
  GridBounds bounds;                    // the bounds used
  long long points = 0;                 // vertices of the mesh
  long long triangles = 0;
  long long inside_pixels = 0;          // pixels with data
  long long nodata_pixels = 0;          // pixels outside the hull
};

// Inputs:
//   points    #N sample positions (distinct; merge duplicates first, see
//             point_table.hpp; repeated positions would use the first)
//   values    #N by C values, row-major
//   C         channels, >= 1
// Output: width x height x (C + alpha) image, rows from ymax down to ymin.
Image grid_points(const std::vector<Point2>& points, const std::vector<float>& values, int C,
                  const GridOptions& options, GridStats* stats = nullptr);

// The points' bounding box (may have no area: grid_points then refuses the points).
GridBounds bounding_box(const std::vector<Point2>& points);

}  // namespace ddt
