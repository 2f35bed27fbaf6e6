#include "eval/synthetic_scenes.hpp"

#include "util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>

namespace ddt {

void Scene::field(double x, double y, float* out) const {
  background(x, y, out);
  for (const SceneLayer& layer : layers) {
    if (layer.sd(x, y) < 0.0) std::copy_n(layer.colour.begin(), channels, out);
  }
}

namespace {

constexpr double kPi = std::numbers::pi;

// ---------------------------------------------------------------------------
// Rendering

// Fraction of the square [-1/2, 1/2]^2 where c + a u + b v < 0.
// Reflections (u -> -u, v -> -v, u <-> v) leave the fraction unchanged, so
// take a >= b >= 0; then the area below the level z of a u + b v, counted
// from the corner where it is smallest, is a triangle, a trapezoid, or the
// square minus a triangle.
double negative_fraction(double c, double a, double b) {
  a = std::abs(a);
  b = std::abs(b);
  if (a < b) std::swap(a, b);
  const double z = 0.5 * (a + b) - c;  // in [0, a + b] when the line crosses
  if (z <= 0.0) return 0.0;
  if (z >= a + b) return 1.0;
  if (z < b) return z * z / (2.0 * a * b);
  if (z <= a) return (z - 0.5 * b) / a;
  const double t = a + b - z;
  return 1.0 - t * t / (2.0 * a * b);
}

// At this depth of 2x2 subdivision (cells 1/256 of a pixel wide) a cell the
// boundary still bends in takes the value at its centre. Only the few cells
// around a corner or junction get here, so the error is a few 256^-2 of the
// contrast.
constexpr int kMaxDepth = 8;
// A boundary counts as straight over a cell when the layer's distance bound
// deviates from a plane by at most this fraction of a pixel at the 3x3 grid
// of samples: the coverage error is then a small multiple of it.
constexpr double kStraightness = 1e-4;

class Renderer {
 public:
  Renderer(const Scene& scene, double pixel_size)
      : scene_(scene), tolerance_(kStraightness * pixel_size) {}

  // Average of the scene over [x0, x1] x [y0, y1], added to out[0..channels).
  void average(double x0, double y0, double x1, double y1, int depth, double weight,
               double* out) const {
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    const double radius = 0.5 * std::hypot(x1 - x0, y1 - y0);

    // Walk the layers from the top: a layer covering the whole cell hides
    // everything under it; the 1-Lipschitz bound makes "|sd| > radius" a
    // proof that the boundary misses the cell.
    int covering = -1, crossing = -1, n_crossing = 0;
    double crossing_sd = 0.0;
    for (int k = static_cast<int>(scene_.layers.size()) - 1; k >= 0; --k) {
      const double d = scene_.layers[k].sd(cx, cy);
      if (d < -radius) {
        covering = k;
        break;
      }
      if (d <= radius) {
        if (n_crossing++ == 0) {
          crossing = k;
          crossing_sd = d;
        }
      }
    }

    if (n_crossing == 0) {
      add_base(covering, x0, y0, x1, y1, weight, out);
      return;
    }
    if (n_crossing == 1) {
      double c = 0.0, a = 0.0, b = 0.0;
      if (fit_plane(scene_.layers[crossing], x0, y0, x1, y1, crossing_sd, c, a, b)) {
        const double inside = negative_fraction(c, a, b);
        add_colour(scene_.layers[crossing], weight * inside, out);
        add_base(covering, x0, y0, x1, y1, weight * (1.0 - inside), out);
        return;
      }
    }
    if (depth < kMaxDepth) {
      const double w = 0.25 * weight;
      average(x0, y0, cx, cy, depth + 1, w, out);
      average(cx, y0, x1, cy, depth + 1, w, out);
      average(x0, cy, cx, y1, depth + 1, w, out);
      average(cx, cy, x1, y1, depth + 1, w, out);
      return;
    }
    float value[3];
    scene_.field(cx, cy, value);
    for (int ch = 0; ch < scene_.channels; ++ch) out[ch] += weight * value[ch];
  }

 private:
  // Least-squares plane c + a u + b v through the layer's distance bound at
  // the 3x3 grid u, v in {-1/2, 0, 1/2} of the cell; false when some sample
  // is further than the tolerance from it (curved boundary, corner, or two
  // sides of a thin shape).
  bool fit_plane(const SceneLayer& layer, double x0, double y0, double x1, double y1,
                 double centre_sd, double& c, double& a, double& b) const {
    const double xs[3] = {x0, 0.5 * (x0 + x1), x1};
    const double ys[3] = {y0, 0.5 * (y0 + y1), y1};
    double f[3][3];
    double sum = 0.0, su = 0.0, sv = 0.0;
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        f[j][i] = (i == 1 && j == 1) ? centre_sd : layer.sd(xs[i], ys[j]);
        sum += f[j][i];
        su += (i - 1) * 0.5 * f[j][i];
        sv += (j - 1) * 0.5 * f[j][i];
      }
    }
    c = sum / 9.0;
    a = su / 1.5;  // sum of u^2 over the grid
    b = sv / 1.5;
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        const double plane = c + a * (i - 1) * 0.5 + b * (j - 1) * 0.5;
        if (std::abs(f[j][i] - plane) > tolerance_) return false;
      }
    }
    return true;
  }

  void add_colour(const SceneLayer& layer, double weight, double* out) const {
    for (int ch = 0; ch < scene_.channels; ++ch) out[ch] += weight * layer.colour[ch];
  }

  // What lies under the crossing layers: the covering layer's colour, or the
  // background integrated by 2x2 Gauss-Legendre (exact up to degree 3, so a
  // linear ramp comes out as its value at the cell centre).
  void add_base(int covering, double x0, double y0, double x1, double y1, double weight,
                double* out) const {
    if (covering >= 0) {
      add_colour(scene_.layers[covering], weight, out);
      return;
    }
    static constexpr double node = 0.5773502691896258;  // 1 / sqrt(3)
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    const double hx = node * 0.5 * (x1 - x0), hy = node * 0.5 * (y1 - y0);
    const double w = 0.25 * weight;
    float value[3];
    for (double dy : {-hy, hy}) {
      for (double dx : {-hx, hx}) {
        scene_.background(cx + dx, cy + dy, value);
        for (int ch = 0; ch < scene_.channels; ++ch) out[ch] += w * value[ch];
      }
    }
  }

  const Scene& scene_;
  double tolerance_;
};

// ---------------------------------------------------------------------------
// Shapes: exact signed distances (negative inside) unless noted.

// Not std::hypot: its overflow guard costs several times a square root, and
// the arguments here are unit-square distances.
double length(double x, double y) { return std::sqrt(x * x + y * y); }

// Disk of the given centre and radius.
double sd_disk(double x, double y, double cx, double cy, double r) {
  return length(x - cx, y - cy) - r;
}

// Points within r of the segment (ax, ay)-(bx, by): a bar with round caps.
double sd_capsule(double x, double y, double ax, double ay, double bx, double by, double r) {
  const double px = x - ax, py = y - ay, dx = bx - ax, dy = by - ay;
  const double t = std::clamp((px * dx + py * dy) / (dx * dx + dy * dy), 0.0, 1.0);
  return length(px - t * dx, py - t * dy) - r;
}

// Axis-aligned rectangle of the given centre and half sizes: square corners.
double sd_box(double x, double y, double cx, double cy, double hx, double hy) {
  const double qx = std::abs(x - cx) - hx, qy = std::abs(y - cy) - hy;
  return length(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0);
}

// Points within r of the circular arc of radius R about (cx, cy) that starts
// at angle a0 (screen angle: 0 right, pi/2 down) and sweeps `sweep` radians
// clockwise on screen. Inside the sweep the nearest arc point is on the
// radius through p; outside, distance along the circle grows monotonically
// away from p's angle, so the nearest point is an end point.
struct ThickArc {
  double cx, cy, R, a0, sweep, r;
  double ex0, ey0, ex1, ey1;  // end points relative to the centre

  ThickArc(double cx_, double cy_, double R_, double a0_, double sweep_, double r_)
      : cx(cx_), cy(cy_), R(R_), a0(a0_), sweep(sweep_), r(r_),
        ex0(R * std::cos(a0)), ey0(R * std::sin(a0)),
        ex1(R * std::cos(a0 + sweep)), ey1(R * std::sin(a0 + sweep)) {}

  double sd(double x, double y) const {
    const double px = x - cx, py = y - cy;
    const double turn = 2.0 * kPi;
    const double rel = std::fmod(std::atan2(py, px) - a0 + 2.0 * turn, turn);
    if (rel <= sweep) return std::abs(length(px, py) - R) - r;
    return std::min(length(px - ex0, py - ey0), length(px - ex1, py - ey1)) - r;
  }
};

// Signed distance to the nearest multiple of `cell`: positive in even cells
// (floor(t / cell) even), negative in odd ones, |value| = distance.
double signed_cell_distance(double t, double cell) {
  const double k = std::floor(t / cell);
  const double f = t - k * cell;
  const double d = std::min(f, cell - f);
  return std::fmod(k, 2.0) == 0.0 ? d : -d;
}

constexpr float kDark = 0.2f;
constexpr float kBright = 0.8f;

std::function<void(double, double, float*)> constant_background(float v) {
  return [v](double, double, float* out) { out[0] = v; };
}

Scene grey_scene(std::string name, std::string description, float background,
                 std::function<double(double, double)> sd, float colour) {
  Scene s;
  s.name = std::move(name);
  s.description = std::move(description);
  s.channels = 1;
  s.background = constant_background(background);
  s.layers.push_back(SceneLayer{std::move(sd), {colour, colour, colour}});
  return s;
}

Scene edge_scene(int degrees) {
  // Through (0.52, 0.5) rather than the centre, so the edge does not fall on
  // pixel boundaries at power-of-two sizes.
  const double t = degrees * kPi / 180.0;
  const double nx = std::cos(t), ny = std::sin(t);  // towards the bright side
  char name[16];
  std::snprintf(name, sizeof name, "edge_%02d", degrees);
  Scene scene = grey_scene(name,
                           "step edge through (0.52, 0.5) turned " + std::to_string(degrees) +
                               " degrees clockwise from vertical; 0.2 left, 0.8 right",
                           kDark,
                           [nx, ny](double x, double y) { return -(nx * (x - 0.52) + ny * (y - 0.5)); },
                           kBright);
  scene.step_edge = SceneStepEdge{0.52, 0.5, nx, ny, kDark, kBright};
  return scene;
}

}  // namespace

std::vector<Scene> standard_scenes() {
  std::vector<Scene> scenes;
  for (int degrees : {0, 10, 30, 45, 63}) scenes.push_back(edge_scene(degrees));

  scenes.push_back(grey_scene(
      "thin_line",
      "dark segment (0.08, 0.30)-(0.92, 0.64), 1/192 wide with round ends, on 0.8",
      kBright,
      [](double x, double y) { return sd_capsule(x, y, 0.08, 0.30, 0.92, 0.64, 1.0 / 384.0); },
      kDark));

  scenes.push_back(grey_scene(
      "disk", "bright disk, centre (0.47, 0.53), radius 0.3, on 0.2", kDark,
      [](double x, double y) { return sd_disk(x, y, 0.47, 0.53, 0.3); }, kBright));

  scenes.push_back(grey_scene(
      "strokes",
      "dark letter-like strokes 0.05 wide on 0.8: an 'A' of two round-ended bars and a "
      "crossbar, an 'S' of two arcs",
      kBright,
      [top = ThickArc(0.72, 0.35, 0.15, kPi / 2, 4 * kPi / 3, 0.025),
       bottom = ThickArc(0.72, 0.65, 0.15, -kPi / 2, 4 * kPi / 3, 0.025)](double x, double y) {
        const auto letter_a = [&] {
          const double r = 0.025;
          return std::min({sd_capsule(x, y, 0.27, 0.2, 0.1, 0.8, r),
                           sd_capsule(x, y, 0.27, 0.2, 0.44, 0.8, r),
                           sd_box(x, y, 0.27, 0.6, 0.12, r)});
        };
        const auto letter_s = [&] { return std::min(top.sd(x, y), bottom.sd(x, y)); };
        // The 'A' lies in x <= 0.465 and the 'S' in x >= 0.545: the far
        // letter is skipped when the near one is closer than that gap.
        if (x < 0.505) {
          const double d = letter_a();
          return d <= 0.545 - x ? d : std::min(d, letter_s());
        }
        const double d = letter_s();
        return d <= x - 0.465 ? d : std::min(d, letter_a());
      },
      kDark));

  {
    Scene s;
    s.name = "ramp";
    s.description = "linear ramp 0.1 + 0.48 x + 0.32 y";
    s.background = [](double x, double y, float* out) {
      out[0] = static_cast<float>(0.1 + 0.48 * x + 0.32 * y);
    };
    scenes.push_back(std::move(s));
  }
  {
    Scene s;
    s.name = "smooth_waves";
    s.description =
        "0.5 + 0.2 sin(2pi(1.3x + 0.1)) cos(2pi(0.9y - 0.2)) + 0.1 cos(3pi |p - (0.4, 0.6)|)";
    s.background = [](double x, double y, float* out) {
      out[0] = static_cast<float>(0.5 +
                                  0.2 * std::sin(2 * kPi * (1.3 * x + 0.1)) *
                                      std::cos(2 * kPi * (0.9 * y - 0.2)) +
                                  0.1 * std::cos(3 * kPi * length(x - 0.4, y - 0.6)));
    };
    scenes.push_back(std::move(s));
  }
  {
    Scene s;
    s.name = "colour_regions";
    s.description =
        "RGB: orange above, blue below the curve y = 0.5 + 0.12 sin(2pi(1.2x + 0.1))";
    s.channels = 3;
    s.background = [](double, double, float* out) {
      out[0] = 0.9f;
      out[1] = 0.55f;
      out[2] = 0.15f;
    };
    // (curve - y) / L is 1-Lipschitz when L >= sqrt(1 + max|curve'|^2); it is
    // a distance bound, not the exact distance.
    const double slope = 0.12 * 2 * kPi * 1.2;
    const double lipschitz = std::sqrt(1.0 + slope * slope);
    s.layers.push_back(SceneLayer{
        [lipschitz](double x, double y) {
          const double curve = 0.5 + 0.12 * std::sin(2 * kPi * (1.2 * x + 0.1));
          return (curve - y) / lipschitz;
        },
        {0.15f, 0.35f, 0.8f}});
    scenes.push_back(std::move(s));
  }

  scenes.push_back(grey_scene(
      "checker_rotated",
      "checkerboard of 1/16-wide cells (4 pixels at 64x64) turned 25 degrees, 0.2 and 0.8",
      kDark,
      [](double x, double y) {
        const double t = 25.0 * kPi / 180.0;
        const double c = std::cos(t), s = std::sin(t);
        const double cell = 1.0 / 16.0;
        // Offset so that no grid line passes through the square's centre.
        const double u = c * (x - 0.5) + s * (y - 0.5) + 0.013;
        const double v = -s * (x - 0.5) + c * (y - 0.5) + 0.029;
        const double gu = signed_cell_distance(u, cell);
        const double gv = signed_cell_distance(v, cell);
        // The boundary is every grid line, so min(|gu|, |gv|) is the exact
        // distance; cells with odd floor(u) + floor(v) (signs differ) are inside.
        const double d = std::min(std::abs(gu), std::abs(gv));
        return (gu < 0) != (gv < 0) ? -d : d;
      },
      kBright));

  return scenes;
}

const Scene& find_scene(const std::string& name) {
  static const std::vector<Scene> scenes = standard_scenes();
  for (const Scene& s : scenes) {
    if (s.name == name) return s;
  }
  std::string names;
  for (const Scene& s : scenes) names += (names.empty() ? "" : ", ") + s.name;
  throw Error("unknown scene '" + name + "'; valid names: " + names);
}

Image render_scene(const Scene& scene, int width, int height) {
  if (width < 1 || height < 1) {
    throw Error("render_scene: size must be at least 1x1, got " + std::to_string(width) + "x" +
                std::to_string(height));
  }
  if (scene.channels != 1 && scene.channels != 3) {
    throw Error("render_scene: scene '" + scene.name + "' has " +
                std::to_string(scene.channels) + " channels; expected 1 or 3");
  }
  const bool complete = scene.background && std::all_of(scene.layers.begin(), scene.layers.end(),
                                                        [](const SceneLayer& l) { return bool(l.sd); });
  if (!complete) throw Error("render_scene: scene '" + scene.name + "' has an empty function");

  Image image(width, height, scene.channels);
  const Renderer renderer(scene, std::min(1.0 / width, 1.0 / height));
  double sum[3];
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      sum[0] = sum[1] = sum[2] = 0.0;
      // Edges as i / W rather than accumulated steps, so neighbouring pixels
      // share their boundary exactly.
      renderer.average(static_cast<double>(i) / width, static_cast<double>(j) / height,
                       static_cast<double>(i + 1) / width, static_cast<double>(j + 1) / height,
                       0, 1.0, sum);
      for (int ch = 0; ch < scene.channels; ++ch) image.at(i, j, ch) = static_cast<float>(sum[ch]);
    }
  }
  return image;
}

}  // namespace ddt
