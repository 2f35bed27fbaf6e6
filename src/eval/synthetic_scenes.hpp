#pragma once
// Analytic test scenes: images known exactly at every resolution, so an
// upscaler's output can be scored against the true high-resolution answer.
//
// A scene is a function on the unit square [0,1] x [0,1] (x right, y down),
// made of a smooth background with piecewise-constant layers painted over
// it. Rendering at W x H box-filters it: pixel (i, j) is the average of the
// scene over [i/W, (i+1)/W] x [j/H, (j+1)/H], the footprint of a camera
// pixel. This agrees with the pixel-centre convention of image.hpp: sample
// (i, j) sits at unit-square point ((i + 0.5) / W, (j + 0.5) / H).
//
// Errors: functions throw ddt::Error (unknown scene name, bad size).

#include "util/image.hpp"

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace ddt {

// A region of constant colour. `sd` is a signed distance bound: negative
// inside, positive outside, zero on the boundary, and 1-Lipschitz, so no
// boundary point lies closer to p than |sd(p)|. The renderer relies on this
// to skip pixels the boundary cannot reach.
struct SceneLayer {
  std::function<double(double x, double y)> sd;
  std::array<float, 3> colour{};  // the first `channels` entries are used
};

// A scene that is one straight step edge: the line through (x, y) with unit
// normal (nx, ny) (unit-square coordinates), `low` behind it and `high` on
// the normal's side. What the edge-sharpness measures need to know.
struct SceneStepEdge {
  double x = 0, y = 0, nx = 1, ny = 0;
  float low = 0, high = 1;
};

struct Scene {
  std::string name;         // short and stable, e.g. "edge_30"
  std::string description;  // one line: what it shows and where
  int channels = 1;         // 1 (grey) or 3 (RGB)

  // Smooth (at least C^2) field under all layers; writes `channels` floats.
  std::function<void(double x, double y, float* out)> background;
  // Painted in order: a later layer covers earlier ones where they overlap.
  std::vector<SceneLayer> layers;
  // Set for the straight step edges (edge_*), absent for every other scene.
  std::optional<SceneStepEdge> step_edge;

  // The scene's value at point (x, y) of the unit square; writes `channels`
  // floats. Points exactly on a layer boundary count as outside the layer.
  void field(double x, double y, float* out) const;
};

// The standard test set, in a fixed order (all values in 0..1):
//   edge_00, edge_10, edge_30, edge_45, edge_63
//       step edge through (0.52, 0.5) turned 0/10/30/45/63 degrees clockwise
//       from vertical; 0.2 on the left, 0.8 on the right
//   thin_line      dark segment 1/192 wide (1/3 pixel at 64x64), ~22 degrees
//   disk           bright disk, centre (0.47, 0.53), radius 0.3
//   strokes        dark letter-like 'A' (bars) and 'S' (arcs), strokes 0.05 wide
//   ramp           linear ramp 0.1 + 0.48 x + 0.32 y
//   smooth_waves   low-frequency sinusoids plus a radial ripple, 0.2..0.8
//   colour_regions RGB: orange above, blue below a sinusoidal boundary
//   checker_rotated checkerboard of 1/16-wide cells turned 25 degrees
std::vector<Scene> standard_scenes();

// The standard scene called `name`; throws ddt::Error listing valid names.
// The reference stays valid for the life of the program.
const Scene& find_scene(const std::string& name);

// Box-filtered rendering of `scene` at width x height (each >= 1), channels
// = scene.channels. Accurate to about 1e-3 per pixel: pixels the layer
// boundaries do not touch are integrated by 2x2 Gauss-Legendre quadrature
// (exact for cubics, so a linear ramp is exact); touched pixels are
// subdivided until the boundary is straight to within a small fraction of a
// pixel, then its coverage is computed exactly for that straight line.
// Complexity: O(width * height * layers), plus O(width + height) extra work
// per boundary crossing the image. Single-threaded and deterministic; safe to
// call from several threads at once.
Image render_scene(const Scene& scene, int width, int height);

}  // namespace ddt
