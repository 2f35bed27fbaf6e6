#include "eval/sequence_scenes.hpp"

#include "eval/synthetic_scenes.hpp"
#include "util/error.hpp"

#include <algorithm>
#include <cmath>

namespace ddt {
namespace {

constexpr double kPi = 3.14159265358979323846;

// `scene` moved rigidly: the point (x, y) of the moved scene shows the
// point of the original that the inverse motion takes it to (a turn by
// `angle` about (cx, cy), then a shift by (dx, dy)). Distances are kept,
// so the layers' signed distances stay 1-Lipschitz, as render_scene needs.
Scene moved(const Scene& scene, double dx, double dy, double angle = 0, double cx = 0.5, double cy = 0.5) {
  const double c = std::cos(angle), s = std::sin(angle);
  auto back = [=](double x, double y, double& u, double& v) {
    const double px = x - dx - cx, py = y - dy - cy;
    u = cx + c * px + s * py;
    v = cy - s * px + c * py;
  };
  Scene out = scene;
  out.step_edge.reset();
  out.background = [bg = scene.background, back](double x, double y, float* value) {
    double u, v;
    back(x, y, u, v);
    bg(u, v, value);
  };
  for (SceneLayer& layer : out.layers)
    layer.sd = [sd = layer.sd, back](double x, double y) {
      double u, v;
      back(x, y, u, v);
      return sd(u, v);
    };
  return out;
}

Scene grey(float background, std::function<double(double, double)> sd, float colour) {
  Scene s;
  s.channels = 1;
  s.background = [background](double, double, float* out) { out[0] = background; };
  s.layers.push_back(SceneLayer{std::move(sd), {colour, colour, colour}});
  return s;
}

// Separable box weights: for each output index, the photograph indices its
// footprint overlaps and the overlap lengths (divided by the footprint).
struct Weights {
  std::vector<int> first;
  std::vector<std::vector<double>> w;
};

Weights box_weights(double origin, double footprint, int count, int photo_size, const char* axis) {
  Weights out;
  for (int i = 0; i < count; ++i) {
    const double a = origin + i * footprint, b = a + footprint;
    if (a < -1e-9 || b > photo_size + 1e-9)
      throw Error(std::string("the photograph is too small for the scene along ") + axis + " (" +
                  std::to_string(photo_size) + " pixels)");
    const int k0 = std::max(0, static_cast<int>(std::floor(a)));
    const int k1 = std::min(photo_size - 1, static_cast<int>(std::ceil(b)) - 1);
    out.first.push_back(k0);
    std::vector<double> w;
    for (int k = k0; k <= k1; ++k) w.push_back((std::min(b, k + 1.0) - std::max(a, double(k))) / footprint);
    out.w.push_back(std::move(w));
  }
  return out;
}

}  // namespace

const std::vector<SequenceScene>& sequence_scenes() {
  static const std::vector<SequenceScene> scenes = {
      {"disk", "bright disk (radius 0.2) on dark, moving right and down at (1, 0.5) px a frame", false},
      {"bar", "dark bar 0.06 wide, 0.7 long, turning about the centre at 1 degree a frame", false},
      {"strokes", "dark 'A' and 'S' strokes 0.05 wide moving left and down at (0.75, 0.5) px a frame", false},
      {"pan", "a photograph panned at (0.5, 0.25) px a frame, 2x2 photograph pixels a pixel", true},
      {"zoom", "a photograph zoomed in about its centre by 0.5 % a frame", true},
  };
  return scenes;
}

const SequenceScene& find_sequence_scene(const std::string& name) {
  std::string names;
  for (const SequenceScene& s : sequence_scenes()) {
    if (s.name == name) return s;
    names += (names.empty() ? "" : ", ") + s.name;
  }
  throw Error("unknown sequence scene '" + name + "' (valid: " + names + ")");
}

Image box_resample(const Image& photo, double x0, double y0, double footprint, int width, int height) {
  if (photo.empty()) throw Error("the scene needs a photograph");
  if (width < 1 || height < 1) throw Error("the frame size must be at least 1x1");
  const Weights wx = box_weights(x0, footprint, width, photo.width, "x");
  const Weights wy = box_weights(y0, footprint, height, photo.height, "y");
  const int C = photo.channels;
  Image rows(width, photo.height, C);  // filtered along x first
  for (int y = 0; y < photo.height; ++y)
    for (int i = 0; i < width; ++i)
      for (int c = 0; c < C; ++c) {
        double sum = 0;
        for (std::size_t k = 0; k < wx.w[i].size(); ++k) sum += wx.w[i][k] * photo.at(wx.first[i] + int(k), y, c);
        rows.at(i, y, c) = static_cast<float>(sum);
      }
  Image out(width, height, C);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      for (int c = 0; c < C; ++c) {
        double sum = 0;
        for (std::size_t k = 0; k < wy.w[j].size(); ++k) sum += wy.w[j][k] * rows.at(i, wy.first[j] + int(k), c);
        out.at(i, j, c) = static_cast<float>(sum);
      }
  return out;
}

Image render_sequence_frame(const std::string& name, double t, int width, int height, const Image* photo) {
  const SequenceScene& scene = find_sequence_scene(name);
  if (width < 1 || height < 1) throw Error("the frame size must be at least 1x1");
  const double px = 1.0 / width, py = 1.0 / height;  // a pixel in unit-square coordinates
  if (scene.photo) {
    if (!photo || photo->empty()) throw Error("the scene '" + name + "' needs a photograph");
    if (name == "pan") return box_resample(*photo, 8 + 0.5 * t * 2, 8 + 0.25 * t * 2, 2.0, width, height);
    // zoom: footprints shrink by 0.5 % a frame about the photograph's centre.
    const double footprint = 2.0 * std::pow(0.995, t);
    return box_resample(*photo, photo->width / 2.0 - footprint * width / 2.0,
                        photo->height / 2.0 - footprint * height / 2.0, footprint, width, height);
  }
  if (name == "disk") {
    const Scene disk = grey(0.2f, [](double x, double y) { return std::hypot(x - 0.3, y - 0.4) - 0.2; }, 0.8f);
    return render_scene(moved(disk, t * px, 0.5 * t * py), width, height);
  }
  if (name == "bar") {
    const Scene bar = grey(0.8f,
                           [](double x, double y) {
                             // a capsule from (0.15, 0.5) to (0.85, 0.5), half width 0.03
                             const double u = std::clamp(x, 0.15, 0.85);
                             return std::hypot(x - u, y - 0.5) - 0.03;
                           },
                           0.2f);
    return render_scene(moved(bar, 0, 0, t * kPi / 180.0), width, height);
  }
  return render_scene(moved(find_scene("strokes"), -0.75 * t * px, 0.5 * t * py), width, height);
}

}  // namespace ddt
