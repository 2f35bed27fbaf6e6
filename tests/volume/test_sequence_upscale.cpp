#include "eval/sequence_experiments.hpp"
#include "eval/sequence_scenes.hpp"
#include "util/error.hpp"
#include "core/check_mesh.hpp"
#include "volume/sequence_upscale.hpp"
#include "volume/volume_upscale.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

using namespace ddt;

namespace {

std::vector<Image> scene_frames(const std::string& name, int count, int step, int size) {
  std::vector<Image> frames;
  for (int k = 0; k < count; ++k) frames.push_back(render_sequence_frame(name, k * step, size, size));
  return frames;
}

std::vector<Image> run(const std::vector<Image>& in, double time_scale, SequenceUpscaleOptions o = {}, int out_w = 0,
                       int out_h = 0, SequenceUpscaleStats* stats = nullptr) {
  const Image& f = in.front();
  std::vector<Image> out;
  std::vector<int> numbers;
  upscale_sequence(
      static_cast<int>(in.size()), f.width, f.height, f.channels, [&](int k) { return in.at(k); },
      out_w ? out_w : f.width, out_h ? out_h : f.height, time_scale, o,
      [&](Image frame, int k) {
        numbers.push_back(k);
        out.push_back(std::move(frame));
      },
      stats);
  for (std::size_t i = 0; i < numbers.size(); ++i) REQUIRE(numbers[i] == static_cast<int>(i));  // in order, each once
  return out;
}

// The default options (the dominant motion's shear, if any), the
// lattice's initial mesh (no shear), and meshes sheared by whole and
// fractional shifts a frame.
std::vector<SequenceUpscaleOptions> initial_meshes() {
  std::vector<SequenceUpscaleOptions> meshes{SequenceUpscaleOptions{}};
  for (const auto& [dx, dy] : {std::pair{0.0, 0.0}, std::pair{2.0, 1.0}, std::pair{-3.5, 0.25}, std::pair{0.0, -6.0}}) {
    SequenceUpscaleOptions o;
    o.shear_dominant_motion = false;
    o.volume.time_shear = {dx, dy};
    meshes.push_back(o);
  }
  // A zoom (0.3, -0.25, zoom 1.04 a frame) and a zoom out without shift.
  for (const std::string motion : {"0.3,-0.25,1.04", "0,0,0.95"}) {
    SequenceUpscaleOptions o;
    set_motion(o, motion);
    meshes.push_back(o);
  }
  return meshes;
}

double psnr(const Image& a, const Image& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += std::pow(double(a.pixels[i]) - b.pixels[i], 2);
  return sum > 0 ? 10 * std::log10(double(a.pixels.size()) / sum) : 99;
}

}  // namespace

TEST_CASE("upscale_sequence: (T - 1) * s + 1 frames, each input frame kept bit for bit at every s-th") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<Image> in(5, Image(9, 7, 3));
  for (Image& f : in)
    for (float& v : f.pixels) v = u(rng);
  for (SequenceUpscaleOptions o : initial_meshes()) {
    CAPTURE(o.volume.time_shear[0]);
    CAPTURE(o.volume.time_shear[1]);
    CAPTURE(o.volume.time_zoom);
    for (const int s : {1, 2, 4}) {
      for (const Render render : {Render::linear, Render::cubic}) {
        o.volume.render = render;
        const std::vector<Image> out = run(in, s, o);
        REQUIRE(out.size() == std::size_t(4 * s + 1));
        int mismatches = 0;
        for (int k = 0; k < 5; ++k) mismatches += out[std::size_t(k * s)].pixels != in[std::size_t(k)].pixels;
        CHECK(mismatches == 0);
      }
    }
  }
  // x3 in space as well: the input pixels sit at the centre of each 3x3 block.
  const std::vector<Image> big = run(in, 2, {}, 27, 21);
  REQUIRE(big.size() == 9);
  int mismatches = 0;
  for (int k = 0; k < 5; ++k)
    for (int y = 0; y < 7; ++y)
      for (int x = 0; x < 9; ++x)
        for (int c = 0; c < 3; ++c) mismatches += big[std::size_t(2 * k)].at(3 * x + 1, 3 * y + 1, c) != in[k].at(x, y, c);
  CHECK(mismatches == 0);
}

TEST_CASE("upscale_sequence: a field linear in x, y and t is exact between the frames, on any initial mesh") {
  std::vector<Image> in;
  auto field = [](double x, double y, double t) { return 0.1 + 0.02 * x + 0.03 * y + 0.05 * t; };
  for (int t = 0; t < 6; ++t) {
    Image f(8, 6, 1);
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 8; ++x) f.at(x, y) = static_cast<float>(field(x, y, t));
    in.push_back(f);
  }
  for (const SequenceUpscaleOptions& o : initial_meshes()) {
    CAPTURE(o.volume.time_shear[0]);
    CAPTURE(o.volume.time_shear[1]);
    CAPTURE(o.volume.time_zoom);
    const std::vector<Image> out = run(in, 4, o);
    REQUIRE(out.size() == 21);
    double worst = 0;
    for (std::size_t g = 0; g < out.size(); ++g)
      for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 8; ++x) worst = std::max(worst, std::abs(out[g].at(x, y) - field(x, y, g / 4.0)));
    CHECK(worst < 2e-6);
  }
}

TEST_CASE("upscale_sequence: a fractional time scale (60/24) samples the instants g / s, in tiles too") {
  std::vector<Image> in;
  auto field = [](double x, double y, double t) { return 0.1 + 0.02 * x + 0.03 * y + 0.05 * t; };
  for (int t = 0; t < 9; ++t) {
    Image f(8, 6, 1);
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 8; ++x) f.at(x, y) = static_cast<float>(field(x, y, t));
    in.push_back(f);
  }
  CHECK(sequence_output_frames(9, 2.5) == 21);
  CHECK(sequence_output_frames(9, 0.5) == 5);
  CHECK(sequence_output_frames(10, 30000.0 / 1001) == 270);  // 9 x 29.97 = 269.7: the last at or before frame 9
  for (const int tile : {0, 2, 3}) {
    for (const double s : {2.5, 60.0 / 25, 0.5}) {
      SequenceUpscaleOptions o;
      o.tile_frames = tile;
      o.margin_frames = 1;
      SequenceUpscaleStats stats;
      const std::vector<Image> out = run(in, s, o, 0, 0, &stats);
      REQUIRE(out.size() == std::size_t(sequence_output_frames(9, s)));
      double worst = 0;
      for (std::size_t g = 0; g < out.size(); ++g)
        for (int y = 0; y < 6; ++y)
          for (int x = 0; x < 8; ++x) worst = std::max(worst, std::abs(out[g].at(x, y) - field(x, y, g / s)));
      CAPTURE(tile);
      CAPTURE(s);
      CHECK(worst < 2e-6);
      if (tile > 0) CHECK(stats.tiles == (8 + tile - 1) / tile);
    }
  }
}

TEST_CASE("upscale_sequence: tiles over time join the untiled result closely - margins make them closer") {
  const std::vector<Image> in = scene_frames("strokes", 25, 4, 48);
  const std::vector<Image> whole = run(in, 4);
  double previous = 0;
  for (const int margin : {0, 1, 2, 4}) {
    SequenceUpscaleOptions o;
    o.tile_frames = 4;
    o.margin_frames = margin;
    SequenceUpscaleStats stats;
    const std::vector<Image> tiled = run(in, 4, o, 0, 0, &stats);
    CHECK(stats.tiles == 6);
    REQUIRE(tiled.size() == whole.size());
    double worst = 99;
    for (std::size_t g = 0; g < whole.size(); ++g) worst = std::min(worst, psnr(tiled[g], whole[g]));
    MESSAGE("tiles of 4 frames, margin " << margin << ": worst frame PSNR against untiled " << worst << " dB");
    CHECK(worst > 25);
    if (margin > 0) CHECK(worst >= previous);
    previous = worst;
  }
}

TEST_CASE("upscale_sequence: DDT beats frame blending on moving edges at x4 (the issue's claim, small)") {
  for (const std::string scene : {"bar", "strokes"}) {
    std::vector<Image> truth;
    for (int t = 0; t <= 16; ++t) truth.push_back(render_sequence_frame(scene, t, 64, 64));
    std::vector<Image> in;
    for (int t = 0; t <= 16; t += 4) in.push_back(truth[std::size_t(t)]);
    const std::vector<Image> ddt = run(in, 4), blend = blend_frames(in, 4);
    double p_ddt = 0, p_blend = 0;
    for (int t = 0; t <= 16; ++t)
      if (t % 4) p_ddt += psnr(ddt[std::size_t(t)], truth[std::size_t(t)]), p_blend += psnr(blend[std::size_t(t)], truth[std::size_t(t)]);
    MESSAGE(scene << ": mean PSNR ddt " << p_ddt / 12 << ", blend " << p_blend / 12);
    CHECK(p_ddt > p_blend + 12 * 3.0);
  }
}

TEST_CASE("upscale_sequence: the graduated optimization (presmooth) gets a fast edge right where plain Lawson stalls") {
  // The disk moves 4 px between kept frames.
  std::vector<Image> truth;
  for (int t = 0; t <= 12; ++t) truth.push_back(render_sequence_frame("disk", t, 48, 48));
  std::vector<Image> in;
  for (int t = 0; t <= 12; t += 4) in.push_back(truth[std::size_t(t)]);
  // On the lattice's initial mesh: the sheared one (dominant motion) already
  // holds the long tetrahedra the smoothing is there to reach.
  SequenceUpscaleOptions lattice;
  lattice.shear_dominant_motion = false;
  SequenceUpscaleOptions plain = lattice;
  plain.volume.presmooth = {};
  const std::vector<Image> graduated = run(in, 4, lattice), unsmoothed = run(in, 4, plain);
  double p_graduated = 0, p_plain = 0;
  for (int t = 0; t <= 12; ++t)
    if (t % 4)
      p_graduated += psnr(graduated[std::size_t(t)], truth[std::size_t(t)]) / 9,
          p_plain += psnr(unsmoothed[std::size_t(t)], truth[std::size_t(t)]) / 9;
  MESSAGE("disk at 4 px a kept frame: mean PSNR graduated " << p_graduated << ", plain " << p_plain);
  CHECK(p_graduated > p_plain + 3.0);
}

TEST_CASE("upscale_sequence: the smoothing narrows to presmooth_along_motion where the mesh starts along a zoom or a "
          "whole-pixel shift, or the frames move by a pixel or less, and a sigma given holds everywhere") {
  const std::vector<Image> in = scene_frames("disk", 4, 4, 32);
  auto with = [](const std::string& motion, double sigma, double along) {
    SequenceUpscaleOptions o;
    set_motion(o, motion);
    o.volume.presmooth = {sigma, sigma, 0.0};
    o.presmooth_along_motion = along;
    return o;
  };
  auto same = [](const std::vector<Image>& a, const std::vector<Image>& b) {
    bool equal = a.size() == b.size();
    for (std::size_t k = 0; equal && k < a.size(); ++k) equal = a[k].pixels == b[k].pixels;
    return equal;
  };
  // Along a given shift: the default is sigma 0.5, not the volume's 1.
  SequenceUpscaleOptions shifted = with("2,1", 1.0, 0.5);
  std::vector<std::string> log;
  shifted.volume.log = [&](const std::string& line) { log.push_back(line); };
  const std::vector<Image> by_default = run(in, 4, shifted);
  CHECK(same(by_default, run(in, 4, with("2,1", 0.5, -1))));
  CHECK_FALSE(same(by_default, run(in, 4, with("2,1", 1.0, -1))));
  CHECK(std::count(log.begin(), log.end(),
                   "presmooth: sigma 0.5 px in space (the mesh starts along the whole-pixel shift)") == 1);
  // Along a zoom too; along a fractional shift and on the lattice's mesh
  // the volume's sigma stays (where the two sigmas give different frames,
  // so that the checks can fail).
  const std::vector<Image> zoom_narrow = run(in, 4, with("0,0,1.02", 0.5, -1));
  CHECK_FALSE(same(zoom_narrow, run(in, 4, with("0,0,1.02", 1.0, -1))));
  CHECK(same(run(in, 4, with("0,0,1.02", 1.0, 0.5)), zoom_narrow));
  const std::vector<Image> fractional_wide = run(in, 4, with("2.5,1", 1.0, -1));
  CHECK_FALSE(same(fractional_wide, run(in, 4, with("2.5,1", 0.5, -1))));
  CHECK(same(run(in, 4, with("2.5,1", 1.0, 0.5)), fractional_wide));
  // Where the frames agree on a motion of a pixel or less (the disk at a
  // pixel a kept frame), narrowed too; a turning bar, on which no one
  // motion agrees, keeps the volume's sigma.
  const std::vector<Image> slow_in = scene_frames("disk", 4, 1, 32);
  SequenceUpscaleOptions slow = with("auto", 1.0, 0.5);
  std::vector<std::string> slow_log;
  slow.volume.log = [&](const std::string& line) { slow_log.push_back(line); };
  const std::vector<Image> slow_default = run(slow_in, 4, slow);
  CHECK(std::count(slow_log.begin(), slow_log.end(),
                   "presmooth: sigma 0.5 px in space (the frames move by a pixel or less)") == 1);
  CHECK(same(slow_default, run(slow_in, 4, with("auto", 0.5, -1))));
  CHECK_FALSE(same(slow_default, run(slow_in, 4, with("auto", 1.0, -1))));
  const std::vector<Image> turning = scene_frames("bar", 4, 4, 32);
  const std::vector<Image> turning_wide = run(turning, 4, with("auto", 1.0, -1));
  CHECK_FALSE(same(turning_wide, run(turning, 4, with("auto", 0.5, -1))));
  CHECK(same(run(turning, 4, with("auto", 1.0, 0.5)), turning_wide));
  // It only narrows: no smoothing stays none.
  CHECK(same(run(in, 4, with("2,1", 0.0, 0.5)), run(in, 4, with("2,1", 0.0, -1))));
  CHECK(same(run(in, 4, with("off", 1.0, 0.5)), run(in, 4, with("off", 1.0, -1))));
}

TEST_CASE("upscale_sequence: one frame is enlarged by the 2D method - bad arguments are refused") {
  const std::vector<Image> one = scene_frames("disk", 1, 1, 16);
  const std::vector<Image> out = run(one, 4, {}, 32, 32);
  REQUIRE(out.size() == 1);
  CHECK(out[0].width == 32);
  auto read = [&](int) { return one[0]; };
  auto write = [](Image, int) {};
  CHECK_THROWS_AS(upscale_sequence(0, 16, 16, 1, read, 16, 16, 4, {}, write), Error);
  CHECK_THROWS_AS(upscale_sequence(1, 16, 16, 1, read, 16, 16, 0, {}, write), Error);
  CHECK_THROWS_AS(upscale_sequence(2, 16, 16, 1, read, 0, 16, 2, {}, write), Error);
  // A frame of another size from the source.
  CHECK_THROWS_AS(upscale_sequence(2, 17, 16, 1, read, 16, 16, 2, {}, write), Error);
}

TEST_CASE("sequence scenes: the truth moves as described - box_resample averages exactly") {
  const Image a = render_sequence_frame("disk", 0, 32, 32), b = render_sequence_frame("disk", 4, 32, 32);
  double mass_a = 0, mass_b = 0, x_a = 0, x_b = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const double wa = a.at(x, y) - 0.2, wb = b.at(x, y) - 0.2;
      mass_a += wa, mass_b += wb, x_a += wa * x, x_b += wb * x;
    }
  CHECK(mass_a == doctest::Approx(mass_b).epsilon(1e-3));   // same disk
  CHECK(x_b / mass_b - x_a / mass_a == doctest::Approx(4.0).epsilon(0.01));  // 1 px a frame
  Image photo(8, 8, 1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) photo.at(x, y) = float(x + 10 * y);
  const Image r = box_resample(photo, 0.5, 1.0, 2.0, 3, 3);  // linear photo: the footprint centre's value
  CHECK(r.at(0, 0) == doctest::Approx(1.0 + 10 * 1.5));
  CHECK(r.at(2, 1) == doctest::Approx(5.0 + 10 * 3.5));
  CHECK_THROWS_AS(box_resample(photo, 4, 0, 2.0, 3, 3), Error);
  CHECK_THROWS_AS(find_sequence_scene("nope"), Error);
  CHECK_THROWS_AS(render_sequence_frame("pan", 0, 8, 8), Error);  // needs a photograph
}

TEST_CASE("motion_delaunay: a zoom's mesh is valid, joins consecutive frames only, tiles the box and follows the zoom") {
  const std::array<int, 3> size{9, 7, 4};
  const core::SimplexMesh<3> lattice = motion_delaunay(size, {0, 0}, 0, 0);
  for (const auto& [zoom, dx, origin] : {std::tuple{0.25, 0.5, 0}, std::tuple{-0.2, -1.0, 3}, std::tuple{0.1, 0.0, 7}}) {
    CAPTURE(zoom);
    CAPTURE(origin);
    const core::SimplexMesh<3> mesh = motion_delaunay(size, {dx, 0.25}, zoom, origin);
    REQUIRE(core::check_mesh<3>(mesh) == "");
    double volume = 0;
    int spanning = 0;
    for (index_t c = 0; c < mesh.slot_count(); ++c) {
      if (!mesh.is_live(c)) continue;
      std::array<core::Vec<3>, 4> p;
      int t_lo = 1 << 20, t_hi = -1;
      for (int i = 0; i < 4; ++i) {
        p[i] = mesh.points[mesh.vertex(c, i)];
        t_lo = std::min(t_lo, int(p[i][2])), t_hi = std::max(t_hi, int(p[i][2]));
      }
      spanning += t_hi - t_lo != 1;
      core::Vec<3> a, b, e;
      for (int k = 0; k < 3; ++k) a[k] = p[1][k] - p[0][k], b[k] = p[2][k] - p[0][k], e[k] = p[3][k] - p[0][k];
      volume += (a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0]) +
                 a[2] * (b[0] * e[1] - b[1] * e[0])) / 6;
    }
    CHECK(spanning == 0);
    CHECK(std::abs(volume - 8.0 * 6 * 3) < 1e-9);
    CHECK(mesh.cell != lattice.cell);  // the zoom's mesh, not the lattice's fallback
  }
  // A zoom past a factor of 1024 (3^7 by frame 7): the lattice's mesh.
  CHECK(motion_delaunay(size, {0, 0}, 2.0, 4).cell == lattice.cell);
}
