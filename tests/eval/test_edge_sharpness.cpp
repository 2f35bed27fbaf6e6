// Tests for edge_sharpness.hpp: the rise width, wobble and overshoot of
// straight step edges whose answer is known, and the truth-based halo.

#include "eval/edge_sharpness.hpp"

#include "eval/classic_resize.hpp"
#include "util/error.hpp"
#include "eval/matlab_resize.hpp"
#include "eval/peer_resize.hpp"
#include "eval/synthetic_scenes.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>

using ddt::Image;
using ddt::StepEdge;

namespace {

constexpr double kPi = std::numbers::pi;

// The edge at `degrees` clockwise from vertical through (cx, cy) (pixels),
// 0.2 behind, 0.8 ahead: the same layout as the edge_* scenes.
StepEdge edge_at(double degrees, double cx, double cy) {
  const double t = degrees * kPi / 180.0;
  return {cx, cy, std::cos(t), std::sin(t), 0.2, 0.8};
}

// A scene of one step edge, in unit-square coordinates, for render_scene.
ddt::Scene step_scene(double degrees) {
  const double t = degrees * kPi / 180.0, nx = std::cos(t), ny = std::sin(t);
  ddt::Scene s;
  s.name = "step";
  s.background = [](double, double, float* out) { out[0] = 0.2f; };
  s.layers.push_back({[nx, ny](double x, double y) { return -(nx * (x - 0.52) + ny * (y - 0.5)); }, {0.8f}});
  return s;
}

// The box-filtered rendering of step_scene at size x size, and its edge.
Image ideal_step(double degrees, int size, StepEdge& edge) {
  edge = edge_at(degrees, 0.52 * size, 0.5 * size);
  return ddt::render_scene(step_scene(degrees), size, size);
}

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// A step blurred by a Gaussian of `sigma` pixels, sampled at the pixel
// centres, its mid-level line displaced along the normal by
// wave(u) (u: the distance along the edge).
template <class Wave>
Image blurred_step(int size, const StepEdge& e, double sigma, Wave wave) {
  Image img(size, size, 1);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double px = x + 0.5 - e.x, py = y + 0.5 - e.y;
      const double across = px * e.nx + py * e.ny, along = -px * e.ny + py * e.nx;
      img.at(x, y) = static_cast<float>(e.low + (e.high - e.low) * normal_cdf((across - wave(along)) / sigma));
    }
  return img;
}

Image blurred_step(int size, const StepEdge& e, double sigma) {
  return blurred_step(size, e, sigma, [](double) { return 0.0; });
}

// z of the normal distribution's 90 % quantile: a Gaussian step rises 10-90 % in 2 z sigma.
constexpr double kZ90 = 1.2815515655446004;

}  // namespace

TEST_CASE("measure_edge_sharpness: an ideal box-filtered step rises in one to two output pixels") {
  // Rendered at 320 x 320 and measured as an x10 enlargement. A pixel
  // grid cannot show an edge sharper than its box-filtered rendering, and
  // the profile between pixel centres is linear: at 0 degrees the edge at x
  // = 166.4 gives samples 0.2 (centre 165.5), 0.56 (166.5, 60 % bright),
  // 0.8 (167.5), so 10 % falls at 165.667, 50 % at 166.333 and 90 % at
  // 167.25: a rise of 1.583 output pixels, the contour 0.067 behind the
  // line. Other angles spread the phases along the edge: between 0.8 (the
  // pixel's own width) and 1.6 output pixels, 0.08-0.16 input pixels at
  // x10, as issue 15 says of the true edge (0.1).
  for (double degrees : {0.0, 10.0, 30.0, 45.0, 63.0}) {
    CAPTURE(degrees);
    StepEdge edge;
    const Image img = ideal_step(degrees, 320, edge);
    const ddt::EdgeSharpness m = ddt::measure_edge_sharpness(img, edge, 10.0);
    CHECK(m.profiles > 500);
    if (degrees == 0.0) {
      CHECK(m.rise_width == doctest::Approx(0.15833).epsilon(1e-3));
      CHECK(m.offset == doctest::Approx(-0.00667).epsilon(1e-2));
      CHECK(m.wobble == doctest::Approx(0.00667).epsilon(1e-2));
    }
    CHECK(m.rise_width > 0.08);
    CHECK(m.rise_width < 0.16);
    CHECK(m.wobble < 0.01);
    CHECK(m.overshoot < 0.01);
  }
}

TEST_CASE("measure_edge_sharpness: a Gaussian-blurred step rises in 2.56 sigma, and wider when blurrier") {
  double previous = 0;
  for (double sigma_input : {0.25, 0.5, 1.0}) {  // input pixels, at x8
    CAPTURE(sigma_input);
    const StepEdge edge = edge_at(30.0, 0.52 * 256, 0.5 * 256);
    const Image img = blurred_step(256, edge, 8.0 * sigma_input);
    const ddt::EdgeSharpness m = ddt::measure_edge_sharpness(img, edge, 8.0);
    CHECK(m.rise_width == doctest::Approx(2 * kZ90 * sigma_input).epsilon(0.01));
    CHECK(m.rise_width > previous);
    previous = m.rise_width;
    CHECK(m.wobble < 1e-3);
    CHECK(m.overshoot < 1e-4);  // float rounding of the levels
  }
  StepEdge ideal_edge;
  const Image ideal = ideal_step(30.0, 256, ideal_edge);
  CHECK(ddt::measure_edge_sharpness(ideal, ideal_edge, 8.0).rise_width < 0.5 * 2 * kZ90 * 0.25);
}

TEST_CASE("measure_edge_sharpness: a wavy edge's wobble is its RMS displacement - a shifted edge's is the shift") {
  const int size = 320;
  const double s = 10.0;
  const StepEdge edge = edge_at(10.0, 0.52 * size, 0.5 * size);
  // Displaced by 0.1 input pixels * sin(2 pi u / 3 input pixels): RMS 0.1 / sqrt 2.
  const Image wavy = blurred_step(size, edge, 3.0, [s](double u) { return 0.1 * s * std::sin(2 * kPi * u / (3 * s)); });
  const ddt::EdgeSharpness m = ddt::measure_edge_sharpness(wavy, edge, s);
  CHECK(m.wobble == doctest::Approx(0.1 / std::sqrt(2.0)).epsilon(0.05));
  CHECK(std::abs(m.offset) < 0.01);
  // Shifted by 0.05 input pixels towards the bright side: offset and wobble 0.05.
  const Image shifted = blurred_step(size, edge, 3.0, [s](double) { return 0.05 * s; });
  const ddt::EdgeSharpness shift = ddt::measure_edge_sharpness(shifted, edge, s);
  CHECK(shift.offset == doctest::Approx(0.05).epsilon(0.02));
  CHECK(shift.wobble == doctest::Approx(0.05).epsilon(0.02));
}

TEST_CASE("measure_edge_sharpness: pixel replication of a slanted edge is jagged, a straight edge is not") {
  // A 30-degree edge at 32 x 32, enlarged x8 by pixel replication: a
  // staircase whose 50 % contour swings about half an input pixel.
  StepEdge lr_edge;
  const Image lr = ideal_step(30.0, 32, lr_edge);
  const Image stairs = ddt::classic_resize(lr, 256, 256, "nearest");
  const StepEdge edge = edge_at(30.0, 0.52 * 256, 0.5 * 256);
  const ddt::EdgeSharpness jagged = ddt::measure_edge_sharpness(stairs, edge, 8.0);
  StepEdge ideal_edge;
  const ddt::EdgeSharpness straight = ddt::measure_edge_sharpness(ideal_step(30.0, 256, ideal_edge), ideal_edge, 8.0);
  CHECK(jagged.wobble > 0.15);
  CHECK(straight.wobble < 0.01);
  CHECK(jagged.overshoot < 1e-4);  // replication never leaves the input's range
}

TEST_CASE("measure_edge_sharpness: overshoot is the worst excursion in the measured band") {
  StepEdge edge;
  Image img = ideal_step(0.0, 160, edge);  // vertical edge at x = 83.2
  const ddt::EdgeSharpness clean = ddt::measure_edge_sharpness(img, edge, 10.0);
  CHECK(clean.overshoot < 1e-3);
  img.at(88, 80) = 0.8f + 0.018f;  // 0.5 input pixels beyond the edge: 3 % of the 0.6 step
  img.at(120, 80) = 1.0f;          // 3.7 input pixels away: outside the band
  img.at(5, 80) = 0.0f;            // far behind, outside too
  CHECK(ddt::measure_edge_sharpness(img, edge, 10.0).overshoot == doctest::Approx(3.0).epsilon(1e-3));
  img.at(78, 80) = 0.2f - 0.03f;  // 5 % below the low level, behind the edge
  CHECK(ddt::measure_edge_sharpness(img, edge, 10.0).overshoot == doctest::Approx(5.0).epsilon(1e-3));
  // Lanczos rings beside a step: well over 1 % at x4.
  StepEdge lr_edge;
  const Image lr = ideal_step(30.0, 40, lr_edge);
  const ddt::EdgeSharpness lanczos =
      ddt::measure_edge_sharpness(ddt::classic_resize(lr, 160, 160, "lanczos"), edge_at(30.0, 0.52 * 160, 80), 4.0);
  CHECK(lanczos.overshoot > 1.0);
}

TEST_CASE("measure_edge_sharpness: no room for a profile gives NaN - bad input throws") {
  StepEdge edge;
  const Image small = ideal_step(0.0, 40, edge);
  const ddt::EdgeSharpness none = ddt::measure_edge_sharpness(small, edge, 10.0);  // 4 input pixels wide
  CHECK(none.profiles == 0);
  CHECK(std::isnan(none.rise_width));
  CHECK(std::isnan(none.wobble));
  CHECK(ddt::measure_edge_sharpness(small, edge, 1.0).profiles > 0);
  CHECK_THROWS_AS(ddt::measure_edge_sharpness(Image(), edge, 1.0), ddt::Error);
  CHECK_THROWS_AS(ddt::measure_edge_sharpness(small, edge, 0.0), ddt::Error);
  CHECK_THROWS_AS(ddt::measure_edge_sharpness(small, {20, 20, 1, 1, 0.2, 0.8}, 1.0), ddt::Error);  // not unit
  CHECK_THROWS_AS(ddt::measure_edge_sharpness(small, {20, 20, 1, 0, 0.8, 0.2}, 1.0), ddt::Error);  // high < low
  ddt::EdgeSharpnessOptions other_channel;
  other_channel.channel = 1;
  CHECK_THROWS_AS(ddt::measure_edge_sharpness(small, edge, 1.0, other_channel), ddt::Error);
}

TEST_CASE("truth_halo: the window is one input pixel, the excursion a fraction of the step") {
  // Truth: a vertical step at x = 40 in a 80 x 8 image, 0.2 then 0.8; scale 4.
  Image truth(80, 8, 1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 80; ++x) truth.at(x, y) = x < 40 ? 0.2f : 0.8f;
  auto shifted = [&](int by) {  // the truth moved left by `by` pixels
    Image out(80, 8, 1);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 80; ++x) out.at(x, y) = truth.at(std::min(x + by, 79), y);
    return out;
  };
  ddt::TruthHaloOptions fixed;
  fixed.step = 0.6;
  CHECK(ddt::truth_halo(truth, truth, 4.0, fixed) == 0.0);
  CHECK(ddt::truth_halo(shifted(4), truth, 4.0, fixed) == 0.0);  // within one input pixel
  CHECK(ddt::truth_halo(shifted(5), truth, 4.0, fixed) == doctest::Approx(1.0));
  CHECK(ddt::truth_halo(shifted(5), truth, 5.0, fixed) == 0.0);
  Image bump = truth;
  bump.at(60, 3) = 0.8f + 0.03f;  // 5 % of the step above the bright side
  CHECK(ddt::truth_halo(bump, truth, 4.0, fixed) == doctest::Approx(0.05).epsilon(1e-4));
  CHECK(ddt::truth_halo(bump, truth, 4.0) == doctest::Approx(0.05).epsilon(1e-4));  // the truth's range: 0.6
  // Local step: 0.6 within 3 input pixels (12 output) of the step, flat (skipped) beyond.
  ddt::TruthHaloOptions local;
  local.local = true;
  CHECK(ddt::truth_halo(bump, truth, 4.0, local) == 0.0);  // x = 60 is 20 pixels from the step
  bump.at(50, 3) = 0.8f + 0.03f;                            // 10 pixels: the step is in the wider window
  CHECK(ddt::truth_halo(bump, truth, 4.0, local) == doctest::Approx(0.05).epsilon(1e-4));
  // A flat truth has no step: nothing counts.
  CHECK(ddt::truth_halo(bump, Image(80, 8, 1, 0.5f), 4.0) == 0.0);
  ddt::TruthHaloOptions shaved = fixed;
  shaved.shave = 3;
  bump = truth;
  bump.at(2, 2) = 0.5f;  // a halo, but in the shaved border
  bump.at(1, 1) = 0.0f;
  CHECK(ddt::truth_halo(bump, truth, 4.0, shaved) == 0.0);
  CHECK(ddt::truth_halo(bump, truth, 4.0, fixed) == doctest::Approx(0.5));
  CHECK_THROWS_AS(ddt::truth_halo(Image(80, 8, 2), truth, 4.0), ddt::Error);
  CHECK_THROWS_AS(ddt::truth_halo(truth, truth, 0.5), ddt::Error);
  ddt::TruthHaloOptions everything;
  everything.shave = 4 * 80;
  CHECK_THROWS_AS(ddt::truth_halo(truth, truth, 4.0, everything), ddt::Error);
}

TEST_CASE("truth_halo: bicubic and Lanczos fail the 1 % bound beside a step edge, pixel replication passes") {
  // The protocol of issue 15: LR and truth are box-filtered renderings of
  // one scene; within one input pixel of each output pixel the output may
  // not leave the truth's range by more than 1 % of the step.
  for (double degrees : {0.0, 30.0, 45.0}) {
    CAPTURE(degrees);
    const ddt::Scene scene = step_scene(degrees);
    const int size = 32, s = 4;
    const Image lr = ddt::render_scene(scene, size, size);
    const Image truth = ddt::render_scene(scene, size * s, size * s);
    ddt::TruthHaloOptions options;
    options.shave = s;
    const double nearest = ddt::truth_halo(ddt::classic_resize(lr, size * s, size * s, "nearest"), truth, s, options);
    const double bicubic = ddt::truth_halo(ddt::matlab_imresize_bicubic(lr, size * s, size * s), truth, s, options);
    const double lanczos = ddt::truth_halo(ddt::classic_resize(lr, size * s, size * s, "lanczos"), truth, s, options);
    const double lanczos4 =
        ddt::truth_halo(ddt::peer_resize(lr, size * s, size * s, "opencv-lanczos4"), truth, s, options);
    CHECK(nearest < 1e-4);
    CHECK(bicubic > 0.01);
    CHECK(lanczos > 0.01);
    CHECK(lanczos4 > 0.01);
    // The same verdicts against the scene's known step and the local step.
    for (const bool local : {false, true}) {
      CAPTURE(local);
      ddt::TruthHaloOptions other = options;
      other.step = local ? 0.0 : 0.6;
      other.local = local;
      CHECK(ddt::truth_halo(ddt::classic_resize(lr, size * s, size * s, "nearest"), truth, s, other) < 1e-4);
      CHECK(ddt::truth_halo(ddt::matlab_imresize_bicubic(lr, size * s, size * s), truth, s, other) > 0.01);
    }
  }
}
