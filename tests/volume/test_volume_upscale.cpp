#include "util/error.hpp"
#include "pipeline/upscale.hpp"
#include "eval/volume_experiments.hpp"
#include "eval/volume_fields.hpp"
#include "eval/volume_pictures.hpp"
#include "eval/volume_resample.hpp"
#include "volume/volume_upscale.hpp"
#include "test_support3.hpp"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace ddt;

namespace {

double linear(double x, double y, double z) { return 0.2 + 0.05 * x + 0.03 * y - 0.04 * z; }

// Worst error against the clamped linear field; `margin` input voxels at
// the border are skipped (tricubic with clamped indices is linear only
// where its 4-tap support stays inside).
double worst_linear_error(const Volume& out, int nx, int ny, int nz, double margin = 0) {
  double worst = 0;
  for (int Z = 0; Z < out.nz; ++Z)
    for (int Y = 0; Y < out.ny; ++Y)
      for (int X = 0; X < out.nx; ++X) {
        const double p[3] = {(X + 0.5) * nx / out.nx, (Y + 0.5) * ny / out.ny, (Z + 0.5) * nz / out.nz};
        const int n[3] = {nx, ny, nz};
        bool skip = false;
        for (int a = 0; a < 3; ++a) skip = skip || p[a] < margin || p[a] > n[a] - margin;
        if (skip) continue;
        const double x = std::clamp((X + 0.5) * nx / out.nx, 0.5, nx - 0.5);
        const double y = std::clamp((Y + 0.5) * ny / out.ny, 0.5, ny - 0.5);
        const double z = std::clamp((Z + 0.5) * nz / out.nz, 0.5, nz - 0.5);
        worst = std::max(worst, std::abs(out.at(X, Y, Z) - linear(x, y, z)));
      }
  return worst;
}

VolumeUpscaleOptions method(const std::string& m, const std::string& cost = "variance") {
  VolumeUpscaleOptions o;
  o.method = volume_method_by_name(m);
  o.cost = cost;
  return o;
}

}  // namespace

TEST_CASE("upscale_volume: a linear field is reproduced by every method and render (clamped outside the samples)") {
  const Volume in = test::sampled_volume(6, 5, 7, linear);
  for (const std::string& m : volume_upscale_methods())
    for (const std::string cost : {"variance", "sederberg"})
      for (const Render render : {Render::cubic, Render::linear}) {
        CAPTURE(m);
        CAPTURE(cost);
        CAPTURE(to_string(render));
        VolumeUpscaleOptions o = method(m, cost);
        o.render = render;
        const Volume out = upscale_volume(in, 15, 12, 17, o);
        CHECK(worst_linear_error(out, 6, 5, 7, m == "tricubic" ? 2.0 : 0.0) < 2e-6);
      }
}

TEST_CASE("upscale_volume: the cubic render (default) is closer to smooth fields than the linear one, on the same mesh") {
  for (const std::string name : {"sphere", "hydrogen"}) {
    const VolumeField& field = find_volume_field(name);
    const Volume in = sample_field(field, 12, 12, 12, 6);
    const Volume reference = sample_field(field, 36, 36, 36, 3);
    VolumeUpscaleOptions linear_render = method("ddt");
    linear_render.render = Render::linear;
    VolumeUpscaleStats cubic_stats, linear_stats;
    const double cubic = volume_rmse(upscale_volume(in, 36, 36, 36, method("ddt"), &cubic_stats), reference);
    const double flat = volume_rmse(upscale_volume(in, 36, 36, 36, linear_render, &linear_stats), reference);
    MESSAGE(name << " 12^3 x3: RMSE ddt cubic " << cubic << ", linear " << flat);
    CHECK(cubic_stats.flips.total() == linear_stats.flips.total());
    CHECK(cubic < flat);
  }
}

TEST_CASE("upscale_volume: DDT reproduces the input samples at coinciding positions (x3)") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Volume in(5, 4, 6);
  for (float& v : in.voxels) v = u(rng);
  for (const std::string cost : {"variance", "sederberg"}) {
    const Volume out = upscale_volume(in, 15, 12, 18, method("ddt", cost));
    int mismatches = 0;
    for (int z = 0; z < in.nz; ++z)
      for (int y = 0; y < in.ny; ++y)
        for (int x = 0; x < in.nx; ++x) mismatches += out.at(3 * x + 1, 3 * y + 1, 3 * z + 1) != in.at(x, y, z);
    CHECK(mismatches == 0);
  }
}

TEST_CASE("upscale_volume: DDT (variance) beats trilinear on the sphere, as in the paper's Fig. 9") {
  const VolumeField& sphere = find_volume_field("sphere");
  const Volume in = sample_field(sphere, 12, 12, 12, 6);
  const Volume reference = sample_field(sphere, 36, 36, 36, 3);
  VolumeUpscaleStats st;
  const double ddt = volume_rmse(upscale_volume(in, 36, 36, 36, method("ddt"), &st), reference);
  const double tri = volume_rmse(upscale_volume(in, 36, 36, 36, method("trilinear")), reference);
  MESSAGE("sphere 12^3 x3: RMSE ddt " << ddt << ", trilinear " << tri << ", flips " << st.flips.summary());
  CHECK(st.flips.total() > 0);
  CHECK(st.cost_after < st.cost_before);
  CHECK(ddt < tri);
}

TEST_CASE("upscale_volume: deterministic (same input, same output bits)") {
  const Volume in = sample_field(find_volume_field("hydrogen"), 8, 8, 8, 2);
  const Volume a = upscale_volume(in, 20, 20, 20, method("ddt", "sederberg"));
  const Volume b = upscale_volume(in, 20, 20, 20, method("ddt", "sederberg"));
  CHECK(a.voxels == b.voxels);
}

TEST_CASE("upscale_volume: in slabs, the same output bits for 1 and 2 threads - slabs of default size below 47^3 are "
          "one region") {
  const Volume in = sample_field(find_volume_field("sphere"), 14, 14, 14, 2);
  VolumeUpscaleOptions options = method("ddt");
  options.region_slices = 3;
  Volume one, two;
  VolumeUpscaleStats st1, st2;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = upscale_volume(in, 28, 28, 28, options, &st1);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = upscale_volume(in, 28, 28, 28, options, &st2);
  }
  CHECK(st1.flips.total() > 0);
  CHECK(st1.flips.by_kind == st2.flips.by_kind);
  CHECK(one.voxels == two.voxels);
  CHECK(volume_region_slices(32, 32, 32) == 32);
  CHECK(volume_region_slices(128, 128, 128) == 16);
  CHECK(volume_region_slices(20, 20, 2000) == core::default_region_cells / (6 * 19 * 19));  // 6 tetrahedra a cube
}

TEST_CASE("upscale_volume: a single slice goes through the 2D method and is repeated along the thin axis") {
  const Volume in = test::sampled_volume(7, 1, 5, [](double x, double, double z) { return x * z > 6 ? 1.0 : 0.0; });
  VolumeUpscaleStats st;
  const Volume out = upscale_volume(in, 14, 3, 10, method("ddt"), &st);
  CHECK(st.planar);
  Image img(7, 5, 1);
  for (int z = 0; z < 5; ++z)
    for (int x = 0; x < 7; ++x) img.at(x, z) = in.at(x, 0, z);
  UpscaleOptions o;
  o.cost = "variance";
  const Image flat = upscale(img, 14, 10, o);
  for (int Y = 0; Y < 3; ++Y)
    for (int Z = 0; Z < 10; ++Z)
      for (int X = 0; X < 14; ++X) CHECK(out.at(X, Y, Z) == flat.at(X, Z));
  const Volume dot = upscale_volume(Volume(1, 1, 1, 0.5f), 2, 2, 2, method("ddt"));
  CHECK(std::all_of(dot.voxels.begin(), dot.voxels.end(), [](float v) { return v == 0.5f; }));
  // The render and the slopes reach the 2D method.
  VolumeUpscaleOptions linear_render = method("ddt");
  linear_render.render = Render::linear;
  o.render = Render::linear;
  const Volume linear_out = upscale_volume(in, 14, 3, 10, linear_render);
  const Image linear_flat = upscale(img, 14, 10, o);
  int mismatches = 0, differ_from_cubic = 0;
  for (int Z = 0; Z < 10; ++Z)
    for (int X = 0; X < 14; ++X) {
      mismatches += linear_out.at(X, 1, Z) != linear_flat.at(X, Z);
      differ_from_cubic += linear_out.at(X, 1, Z) != out.at(X, 1, Z);
    }
  CHECK(mismatches == 0);
  CHECK(differ_from_cubic > 0);
}

TEST_CASE("upscale_volume: bad arguments are refused") {
  const Volume in(3, 3, 3, 1.0f);
  CHECK_THROWS_AS(upscale_volume(Volume{}, 2, 2, 2), Error);
  CHECK_THROWS_AS(upscale_volume(in, 0, 2, 2), Error);
  CHECK_THROWS_AS(upscale_volume(in, 6, 6, 6, method("bicubic")), Error);
  CHECK_THROWS_AS(upscale_volume(in, 6, 6, 6, method("ddt", "nope")), Error);
}

TEST_CASE("classic_resize_volume: trilinear agrees with Teem's tent kernel - tricubic keeps constants") {
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Volume in(6, 5, 4);
  for (float& v : in.voxels) v = u(rng);
  for (const int s : {2, 3}) {
    const Volume mine = classic_resize_volume(in, 6 * s, 5 * s, 4 * s, "trilinear");
    const Volume teem = teem_resample(in, 6 * s, 5 * s, 4 * s, "tent");
    double worst = 0;
    for (std::size_t i = 0; i < mine.voxels.size(); ++i) worst = std::max(worst, double(std::abs(mine.voxels[i] - teem.voxels[i])));
    CHECK(worst < 1e-5);
  }
  const Volume flat = classic_resize_volume(Volume(4, 4, 4, 0.7f), 9, 9, 9, "tricubic");
  for (float v : flat.voxels) CHECK(v == doctest::Approx(0.7f).epsilon(1e-5));
  CHECK_THROWS_AS(classic_resize_volume(in, 8, 8, 8, "lanczos"), Error);
}

TEST_CASE("sample_field: the sphere's mean is the ball's volume - the hydrogen density peaks at 1 on the z axis") {
  const Volume s = sample_field(find_volume_field("sphere"), 16, 16, 16, 4);
  double mean = 0;
  for (float v : s.voxels) mean += v;
  mean /= s.voxel_count();
  CHECK(mean == doctest::Approx(4.0 / 3.0 * M_PI * 0.35 * 0.35 * 0.35).epsilon(0.02));
  const VolumeField& h = find_volume_field("hydrogen");
  CHECK(h.value(0.5, 0.5, 0.5 + 6.0 / 40.0) == doctest::Approx(1.0));
  CHECK(h.value(0.5 + 6.0 / 40.0, 0.5, 0.5) == doctest::Approx(0.25));
  CHECK_THROWS_AS(find_volume_field("torus"), Error);
  CHECK(volume_psnr(s, s) == INFINITY);
}

TEST_CASE("compare_views: one column per volume, one row per view, values mapped to 0..1") {
  const Volume a = test::sampled_volume(6, 5, 4, [](double x, double, double) { return x; });
  const Volume b(6, 5, 4, 2.0f);
  const Image mip = volume_view(a, VolumeView::mip_z);
  CHECK(mip.width == 6);
  CHECK(mip.at(5, 0) == 5.5f);
  const Image pic = compare_views({&a, &b}, {VolumeView::slice_xy, VolumeView::slice_yz, VolumeView::mip_z}, 0, 4);
  CHECK(pic.width == 4 + 2 * (6 + 4));
  CHECK(pic.height == 4 + (5 + 4) + (4 + 4) + (5 + 4));
  CHECK(pic.at(4 + 10, 4) == 0.5f);  // b's first cell: 2 mapped from [0, 4]
  CHECK_THROWS_AS(compare_views({&a, &mip == nullptr ? &a : &b}, {}, 0, 1), Error);
}

TEST_CASE("run_volume_experiments: a tiny run scores every method") {
  VolumeExperimentOptions o;
  o.size = 6;
  o.scale = 2;
  o.input_ss = 2;
  o.reference_ss = 1;
  o.methods = {"trilinear", "ddt", "ddt:sederberg"};
  const auto rows = run_volume_experiments(o);
  CHECK(rows.size() == 6);
  for (const auto& r : rows) CHECK(std::isfinite(r.psnr));
  CHECK(volume_experiment_table(rows).find("| hydrogen | ddt:sederberg |") != std::string::npos);
  o.methods = {"ddt:nope"};
  CHECK_THROWS_AS(run_volume_experiments(o), Error);
}

TEST_CASE("isosurface_view: a ball is a lit disc in the middle and background at the corners") {
  const Volume ball = sample_field(find_volume_field("sphere"), 16, 16, 16, 2);
  IsoView iso;
  iso.level = 0.5;
  const Image img = isosurface_view(ball, iso, 32);
  CHECK(img.at(16, 16) > 0.8f);  // facing the headlight
  CHECK(img.at(0, 0) == 0.0f);
  CHECK(img.at(31, 31) == 0.0f);
  int lit = 0;
  for (float v : img.pixels) lit += v > 0;
  // The ball's radius is 0.35 of the side; the picture spans the bounding sphere (sqrt(3)/2 of the side).
  const double expected = M_PI * std::pow(0.35 / (std::sqrt(3.0) / 2) * 16, 2);
  CHECK(lit == doctest::Approx(expected).epsilon(0.1));
  const Image row = compare_views({&ball, &ball}, {VolumeView::isosurface}, 0, 1, iso);
  CHECK(row.width == 4 + 2 * (16 + 4));
  CHECK(row.height == 4 + 16 + 4);
}

namespace {

// Three channels, each a different linear function (channel c of voxel
// (x, y, z) at its centre).
double channel_linear(double x, double y, double z, int c) {
  return c == 0 ? linear(x, y, z) : c == 1 ? 1.0 - 0.02 * x + 0.06 * z : -0.5 + 0.01 * x + 0.04 * y + 0.03 * z;
}

Volume three_channels(int nx, int ny, int nz) {
  Volume v(nx, ny, nz, 3, 0.0f);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        for (int c = 0; c < 3; ++c) v.at(x, y, z, c) = static_cast<float>(channel_linear(x + 0.5, y + 0.5, z + 0.5, c));
  return v;
}

}  // namespace

TEST_CASE("upscale_volume: three channels, each linear, are reproduced by every method") {
  const Volume in = three_channels(6, 5, 7);
  for (const std::string& m : volume_upscale_methods()) {
    CAPTURE(m);
    const Volume out = upscale_volume(in, 15, 12, 17, method(m));
    REQUIRE(out.channels == 3);
    REQUIRE(out.voxels.size() == out.voxel_count() * 3);
    double worst = 0;
    const double margin = m == "tricubic" ? 2.0 : 0.0;
    for (int Z = 0; Z < out.nz; ++Z)
      for (int Y = 0; Y < out.ny; ++Y)
        for (int X = 0; X < out.nx; ++X) {
          const double p[3] = {(X + 0.5) * 6 / 15, (Y + 0.5) * 5 / 12, (Z + 0.5) * 7 / 17};
          const int n[3] = {6, 5, 7};
          bool skip = false;
          for (int a = 0; a < 3; ++a) skip = skip || p[a] < margin || p[a] > n[a] - margin;
          if (skip) continue;
          for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(out.at(X, Y, Z, c) - channel_linear(std::clamp(p[0], 0.5, 5.5),
                                                                                   std::clamp(p[1], 0.5, 4.5),
                                                                                   std::clamp(p[2], 0.5, 6.5), c)));
        }
    CHECK(worst < 2e-6);
  }
}

TEST_CASE("upscale_volume: every channel's samples are reproduced bit for bit at coinciding positions (x3)") {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Volume in(5, 4, 6, 2, 0.0f);
  for (float& v : in.voxels) v = u(rng);
  VolumeUpscaleStats st;
  const Volume out = upscale_volume(in, 15, 12, 18, method("ddt"), &st);
  CHECK(st.flips.total() > 0);
  int mismatches = 0;
  for (int z = 0; z < in.nz; ++z)
    for (int y = 0; y < in.ny; ++y)
      for (int x = 0; x < in.nx; ++x)
        for (int c = 0; c < 2; ++c) mismatches += out.at(3 * x + 1, 3 * y + 1, 3 * z + 1, c) != in.at(x, y, z, c);
  CHECK(mismatches == 0);
}

TEST_CASE("upscale_volume: every channel drives the flips (a constant channel beside the sphere changes nothing)") {
  const Volume sphere = sample_field(find_volume_field("sphere"), 10, 10, 10, 4);
  for (const int data_channel : {0, 1}) {
    CAPTURE(data_channel);
    Volume two(10, 10, 10, 2, 0.25f);
    set_volume_channel(two, data_channel, sphere);
    VolumeUpscaleStats one_stats, two_stats;
    const Volume alone = upscale_volume(sphere, 25, 25, 25, method("ddt"), &one_stats);
    const Volume both = upscale_volume(two, 25, 25, 25, method("ddt"), &two_stats);
    CHECK(two_stats.flips.total() == one_stats.flips.total());
    CHECK(one_stats.flips.total() > 0);
    CHECK(volume_channel(both, data_channel).voxels == alone.voxels);
    const Volume constant = volume_channel(both, 1 - data_channel);
    CHECK(std::all_of(constant.voxels.begin(), constant.voxels.end(), [](float v) { return v == 0.25f; }));
  }
}

TEST_CASE("upscale_volume: a single slice of several channels goes through the 2D method, all channels at once") {
  const Volume in = three_channels(6, 5, 1);
  const Volume out = upscale_volume(in, 12, 10, 3, method("ddt"));
  REQUIRE(out.channels == 3);
  Image img(6, 5, 3);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 6; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = in.at(x, y, 0, c);
  UpscaleOptions o;
  o.cost = "variance";
  const Image flat = upscale(img, 12, 10, o);
  int mismatches = 0;
  for (int Z = 0; Z < 3; ++Z)
    for (int Y = 0; Y < 10; ++Y)
      for (int X = 0; X < 12; ++X)
        for (int c = 0; c < 3; ++c) mismatches += out.at(X, Y, Z, c) != flat.at(X, Y, c);
  CHECK(mismatches == 0);
}

TEST_CASE("upscale_volume: a node-centred axis keeps every input sample at every s-th output sample, ends included") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Volume in(5, 4, 6);
  for (float& v : in.voxels) v = u(rng);
  for (const int s : {2, 3, 4}) {
    for (const Render render : {Render::cubic, Render::linear}) {
      CAPTURE(s);
      VolumeUpscaleOptions o = method("ddt");
      o.render = render;
      o.node_centred = {false, false, true};
      const Volume out = upscale_volume(in, 15, 12, (in.nz - 1) * s + 1, o);
      int mismatches = 0;
      for (int z = 0; z < in.nz; ++z)
        for (int y = 0; y < in.ny; ++y)
          for (int x = 0; x < in.nx; ++x) mismatches += out.at(3 * x + 1, 3 * y + 1, s * z) != in.at(x, y, z);
      CHECK(mismatches == 0);
    }
  }
  // A linear field: exact between the samples too, at X / s + 0.5 along z.
  const Volume lin = test::sampled_volume(6, 5, 7, linear);
  VolumeUpscaleOptions o = method("ddt");
  o.node_centred = {false, false, true};
  const Volume out = upscale_volume(lin, 12, 10, 25, o);
  double worst = 0;
  for (int Z = 0; Z < out.nz; ++Z)
    for (int Y = 0; Y < out.ny; ++Y)
      for (int X = 0; X < out.nx; ++X) {
        const double x = std::clamp((X + 0.5) / 2, 0.5, 5.5), y = std::clamp((Y + 0.5) / 2, 0.5, 4.5);
        worst = std::max(worst, std::abs(out.at(X, Y, Z) - linear(x, y, Z / 4.0 + 0.5)));
      }
  CHECK(worst < 2e-6);
}
