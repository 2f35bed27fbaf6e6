#include "eval/sequence_scenes.hpp"
#include "util/error.hpp"
#include "volume/dominant_motion.hpp"
#include "volume/sequence_upscale.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <tuple>

using namespace ddt;

namespace {

// A smooth random texture (a sum of sinusoids) seen through a window that
// moves by (vx, vy) pixels a frame: frame t at (x, y) is texture(x - vx t,
// y - vy t), so the content moves by +(vx, vy).
std::vector<Image> moving_texture(int frames, int size, double vx, double vy, int channels = 3) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  struct Wave {
    double kx, ky, phase, amplitude;
  };
  std::vector<Wave> waves;
  for (int i = 0; i < 24; ++i)
    waves.push_back({(u(rng) - 0.5) * 1.6, (u(rng) - 0.5) * 1.6, u(rng) * 6.283, 0.02 + 0.03 * u(rng)});
  std::vector<Image> out;
  for (int t = 0; t < frames; ++t) {
    Image f(size, size, channels);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        double v = 0.5;
        for (const Wave& w : waves) v += w.amplitude * std::sin(w.kx * (x - vx * t) + w.ky * (y - vy * t) + w.phase);
        for (int c = 0; c < channels; ++c) f.at(x, y, c) = static_cast<float>(v * (1 - 0.1 * c));
      }
    out.push_back(f);
  }
  return out;
}

// The same texture seen by a camera zooming by `zoom` a frame about the
// frame's centre c and moving by d: texture point u is at c + g^t (u - c) +
// d (g^t - 1) / (g - 1) in frame t (g = 1 + zoom), dominant_motion's model.
std::vector<Image> zooming_texture(int frames, int size, double zoom, double dx, double dy) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::array<double, 4>> waves;  // kx, ky, phase, amplitude
  for (int i = 0; i < 24; ++i)
    waves.push_back({(u(rng) - 0.5) * 1.4, (u(rng) - 0.5) * 1.4, u(rng) * 6.283, 0.02 + 0.03 * u(rng)});
  const double c = size / 2.0;
  std::vector<Image> out;
  for (int t = 0; t < frames; ++t) {
    const double g = std::pow(1 + zoom, t), carried = (g - 1) / zoom;
    Image f(size, size, 1);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const double ux = c + (x + 0.5 - c - dx * carried) / g, uy = c + (y + 0.5 - c - dy * carried) / g;
        double v = 0.5;
        for (const auto& w : waves) v += w[3] * std::sin(w[0] * ux + w[1] * uy + w[2]);
        f.at(x, y) = static_cast<float>(v);
      }
    out.push_back(f);
  }
  return out;
}

DominantMotion motion_of(const std::vector<Image>& frames, const DominantMotionOptions& options = {}) {
  return dominant_motion(static_cast<int>(frames.size()), [&](int k) { return frames.at(std::size_t(k)); }, options);
}

double mean_psnr_between(const std::vector<Image>& made, const std::vector<Image>& truth, int step) {
  double sum = 0;
  int count = 0;
  for (std::size_t t = 0; t < truth.size(); ++t) {
    if (t % step == 0) continue;
    double se = 0;
    for (std::size_t i = 0; i < truth[t].pixels.size(); ++i) se += std::pow(double(made[t].pixels[i]) - truth[t].pixels[i], 2);
    sum += 10 * std::log10(double(truth[t].pixels.size()) / se);
    ++count;
  }
  return sum / count;
}

std::vector<Image> upscale_frames(const std::vector<Image>& in, int time_scale, const SequenceUpscaleOptions& o,
                                  SequenceUpscaleStats* stats = nullptr) {
  std::vector<Image> out;
  const Image& f = in.front();
  upscale_sequence(
      static_cast<int>(in.size()), f.width, f.height, f.channels, [&](int k) { return in.at(std::size_t(k)); },
      f.width, f.height, time_scale, o, [&](Image frame, int) { out.push_back(std::move(frame)); }, stats);
  return out;
}

}  // namespace

TEST_CASE("dominant_motion: a translating texture's shift, whole and fractional, either sign") {
  for (const auto& [vx, vy] : {std::pair{3.0, -2.0}, std::pair{-5.0, 0.0}, std::pair{2.5, 1.25}, std::pair{-1.5, 4.75}}) {
    const DominantMotion m = motion_of(moving_texture(6, 96, vx, vy));
    CAPTURE(vx);
    CAPTURE(vy);
    CHECK(m.found);
    CHECK(m.pairs == 5);
    CHECK(m.agreeing == 5);
    CAPTURE(m.median_dx);
    CAPTURE(m.median_dy);
    CHECK(std::abs(m.dx - vx) <= 0.13);
    CHECK(std::abs(m.dy - vy) <= 0.13);
    CHECK(m.dx * 8 == std::round(m.dx * 8));  // rounded to 1/8 pixel
    CHECK(m.zoom == 0);
  }
}

TEST_CASE("dominant_motion: a zoom about the centre, in and out, with a translation") {
  for (const auto& [zoom, dx, dy] : {std::tuple{0.03, 0.0, 0.0}, std::tuple{-0.025, 1.0, -0.5}, std::tuple{0.05, -0.5, 0.25}}) {
    CAPTURE(zoom);
    CAPTURE(dx);
    const DominantMotion m = motion_of(zooming_texture(6, 96, zoom, dx, dy));
    CAPTURE(m.median_zoom);
    CAPTURE(m.zoom_agreeing);
    CHECK(m.found);
    CHECK(m.zoom_agreeing == 5);
    CHECK(std::abs(m.zoom - zoom) <= 0.002);
    CHECK(std::abs(m.dx - dx) <= 0.25);
    CHECK(std::abs(m.dy - dy) <= 0.25);
    CHECK(m.zoom * 65536 == std::round(m.zoom * 65536));  // rounded to 2^-16
  }
  // A pan at the translation's threshold (a pixel a frame) is no zoom.
  const DominantMotion pan = motion_of(moving_texture(6, 96, 1.0, 0.5, 1));
  CHECK(pan.zoom == 0);
  CHECK(pan.dx == (pan.found ? 1.0 : 0.0));
  // A zoom whose edges move under a pixel a frame is left to the lattice.
  const DominantMotion slow = motion_of(zooming_texture(6, 96, 0.01, 0, 0));
  CHECK_FALSE(slow.found);
  CHECK(slow.zoom == 0);
  CHECK(std::abs(slow.median_zoom - 0.01) <= 0.003);
  CHECK(slow.slow);
  CHECK(slow.slow_zoom);
  // What is found is not slow.
  CHECK_FALSE(motion_of(zooming_texture(6, 96, 0.03, 0, 0)).slow);
  CHECK_FALSE(motion_of(moving_texture(6, 96, 3.0, -2.0)).slow);
  // A dot jumping about a flat frame: no translation explains it, and the
  // blocks have too little texture for a zoom.
  std::vector<Image> flat(4, Image(96, 96, 1, 0.5f));
  const int spots[4][2] = {{10, 40}, {60, 20}, {30, 75}, {85, 12}};
  for (int t = 0; t < 4; ++t) flat[t].at(spots[t][0], spots[t][1]) = 1;
  const DominantMotion dot = motion_of(flat);
  CHECK_FALSE(dot.found);
  CHECK(dot.zoom_agreeing == 0);
}

TEST_CASE("dominant_motion: none for still frames, motion of a pixel or less, a rotation, or one frame") {
  const DominantMotion still = motion_of(moving_texture(5, 64, 0, 0));
  CHECK_FALSE(still.found);
  CHECK(still.dx == 0);
  CHECK(still.slow);  // the pairs agree on standing still
  const DominantMotion slow = motion_of(moving_texture(5, 64, 0.75, -0.5));
  CHECK_FALSE(slow.found);  // the lattice pairs it (slow_texture.hpp)
  CHECK(std::abs(slow.median_dx - 0.75) <= 0.25);
  CHECK(slow.slow);
  CHECK_FALSE(slow.slow_zoom);
  std::vector<Image> turning;
  for (int t = 0; t <= 16; t += 4) turning.push_back(render_sequence_frame("bar", t, 64, 64));
  const DominantMotion bar = motion_of(turning);
  CHECK_FALSE(bar.found);
  CHECK_FALSE(bar.slow);  // a turn is no one slow motion either
  CHECK(bar.dx == 0);
  CHECK(bar.dy == 0);
  CHECK_FALSE(motion_of(moving_texture(1, 32, 4, 0)).found);
}

TEST_CASE("dominant_motion: the pairs' frames are asked for in increasing order, each once (a video serves them)") {
  const std::vector<Image> frames = moving_texture(40, 48, 2, 1, 1);
  int next = 0;
  const DominantMotion m = dominant_motion(40, [&](int k) {
    REQUIRE(k >= next);
    next = k + 1;
    return frames.at(std::size_t(k));
  });
  CHECK(m.pairs == 16);
  CHECK(m.found);
  std::vector<Image> mixed = frames;
  mixed[20] = Image(47, 48, 1);
  CHECK_THROWS_AS(motion_of(mixed), Error);
}

TEST_CASE("upscale_sequence: shearing along the dominant motion rebuilds a moving disk and a pan far better") {
  // The disk moves (4, 2) px between kept frames; the texture (2, -3).
  std::vector<Image> disk;
  for (int t = 0; t <= 16; ++t) disk.push_back(render_sequence_frame("disk", t, 64, 64));
  const std::vector<Image> pan = moving_texture(17, 48, 0.5, -0.75);
  for (const std::vector<Image>* truth : {static_cast<const std::vector<Image>*>(&disk), &pan}) {
    std::vector<Image> in;
    for (std::size_t t = 0; t < truth->size(); t += 4) in.push_back((*truth)[t]);
    SequenceUpscaleOptions lattice;
    lattice.shear_dominant_motion = false;
    SequenceUpscaleStats stats;
    const double sheared = mean_psnr_between(upscale_frames(in, 4, {}, &stats), *truth, 4);
    const double unsheared = mean_psnr_between(upscale_frames(in, 4, lattice), *truth, 4);
    MESSAGE(std::string(truth == &disk ? "disk" : "texture") << ": mean PSNR sheared " << sheared << " dB (motion " << stats.motion.dx
                                                  << ", " << stats.motion.dy << "), lattice " << unsheared << " dB");
    CHECK(stats.motion.found);
    CHECK(sheared > unsheared + 3);
  }
}

TEST_CASE("set_motion: auto, off, DX,DY, DX,DY,ZOOM - anything else refused") {
  SequenceUpscaleOptions o;
  CHECK(motion_text(o) == "auto");
  set_motion(o, "-2.5,1");
  CHECK_FALSE(o.shear_dominant_motion);
  CHECK(o.volume.time_shear == std::array<double, 2>{-2.5, 1});
  CHECK(motion_text(o) == "-2.5,1");
  set_motion(o, "0.3,-0.7");  // to 1/8 pixel, as the estimate
  CHECK(o.volume.time_shear == std::array<double, 2>{0.25, -0.75});
  set_motion(o, "off");
  CHECK(motion_text(o) == "off");
  set_motion(o, "0,-1,1.02");  // a zoom, to 2^-16
  CHECK(o.volume.time_zoom == std::round(0.02 * 65536) / 65536);
  CHECK(o.volume.time_shear == std::array<double, 2>{0, -1});
  const std::string zoom_text = motion_text(o);
  set_motion(o, "auto");
  CHECK(o.shear_dominant_motion);
  CHECK(o.volume.time_zoom == 0);
  set_motion(o, zoom_text);  // the text round-trips
  CHECK(o.volume.time_zoom == std::round(0.02 * 65536) / 65536);
  set_motion(o, "-2.5,1");
  CHECK(o.volume.time_zoom == 0);
  for (const char* bad : {"", "on", "1", "1,2,3", "1,x", "nan,0", "0,inf", "2000,0", "1, 2x", "0,0,0.4", "0,0,x",
                          "1,2,1.02x", "1,2,1.02,3", "3,2x"})
    CHECK_THROWS_AS(set_motion(o, bad), Error);
}
