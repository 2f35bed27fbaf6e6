// Volume series (4D: x, y, z, t): upscale_volume on 4-axis volumes, the
// classic series methods, the series field and experiment.
#include "util/error.hpp"
#include "eval/volume_fields.hpp"
#include "eval/volume_pictures.hpp"
#include "eval/volume_resample.hpp"
#include "eval/volume_series_experiments.hpp"
#include "volume/volume_upscale.hpp"

#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace ddt;

namespace {

double linear4(double x, double y, double z, double t) { return 0.2 + 0.05 * x + 0.03 * y - 0.04 * z + 0.06 * t; }

// Sample (x, y, z, t) holds f at (x + 0.5, y + 0.5, z + 0.5, t + 0.5), the mesh's coordinates.
template <class F>
Volume sampled_series(const std::array<int, 4>& n, F f, int channels = 1) {
  Volume v(n, channels, 0.0f);
  for (int t = 0; t < n[3]; ++t)
    for (int z = 0; z < n[2]; ++z)
      for (int y = 0; y < n[1]; ++y)
        for (int x = 0; x < n[0]; ++x)
          for (int c = 0; c < channels; ++c)
            v.at4(x, y, z, t, c) = static_cast<float>(f(x + 0.5, y + 0.5, z + 0.5, t + 0.5) + 0.1 * c);
  return v;
}

Volume random_series(const std::array<int, 4>& n, unsigned seed, int channels = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Volume v(n, channels, 0.0f);
  for (float& x : v.voxels) x = u(rng);
  return v;
}

VolumeUpscaleOptions series_method(const std::string& m, Render render = Render::cubic) {
  VolumeUpscaleOptions o;
  o.method = volume_method_by_name(m);
  o.render = render;
  o.node_centred = {false, false, false, true};
  return o;
}

// Worst error against the linear field, space clamped into the samples'
// box, node-centred time (output step T at input T / s + 0.5, s the time
// scale, or the steps' ratio when 0); `margin` input voxels at the spatial
// border skipped (Catmull-Rom with clamped indices is linear only inside).
double worst_linear4_error(const Volume& out, const std::array<int, 4>& in, double margin = 0,
                           double time_scale = 0) {
  const double st = time_scale > 0 ? time_scale : double(out.nt - 1) / (in[3] - 1);
  double worst = 0;
  for (int T = 0; T < out.nt; ++T)
    for (int Z = 0; Z < out.nz; ++Z)
      for (int Y = 0; Y < out.ny; ++Y)
        for (int X = 0; X < out.nx; ++X) {
          const int O[3] = {X, Y, Z}, N[3] = {out.nx, out.ny, out.nz};
          double p[3];
          bool skip = false;
          for (int a = 0; a < 3; ++a) {
            const double u = (O[a] + 0.5) * in[a] / N[a];
            skip = skip || u < margin || u > in[a] - margin;
            p[a] = std::clamp(u, 0.5, in[a] - 0.5);
          }
          if (skip) continue;
          worst = std::max(worst, std::abs(out.at4(X, Y, Z, T) - linear4(p[0], p[1], p[2], T / st + 0.5)));
        }
  return worst;
}

}  // namespace

TEST_CASE("upscale_volume (series): a 4D linear field is reproduced by every method and render") {
  const std::array<int, 4> in{4, 3, 5, 4};
  const Volume v = sampled_series(in, linear4);
  const std::array<int, 4> out{10, 7, 11, 10};  // x2.5, x2.33, x2.2 in space; x3 in time
  for (const std::string m : {"ddt", "delaunay", "quadrilinear", "tricubic-linear"})
    for (const Render render : {Render::cubic, Render::linear}) {
      CAPTURE(m);
      CAPTURE(to_string(render));
      VolumeUpscaleStats st;
      const Volume o = upscale_volume(v, out, series_method(m, render), &st);
      CHECK(o.size() == out);
      CHECK(worst_linear4_error(o, in, m == "tricubic-linear" ? 2.0 : 0.0) < 3e-6);
      if (m == "ddt" || m == "delaunay") CHECK(st.tetrahedra == 24LL * 3 * 2 * 4 * 3);  // 24 simplices a cell
    }
}

TEST_CASE("upscale_volume (series): a fractional time scale samples the instants g / T, by every method") {
  const std::array<int, 4> in{4, 3, 5, 5};
  const Volume v = sampled_series(in, linear4);
  for (const double T : {2.5, 60.0 / 25, 0.5})
    for (const std::string m : {"ddt", "delaunay", "quadrilinear", "tricubic-linear"}) {
      CAPTURE(T);
      CAPTURE(m);
      // Teem widens its kernels where it reduces (anti-aliasing): the classic methods sample only at T >= 1.
      if (T < 1 && !is_mesh_method(volume_method_by_name(m))) continue;
      VolumeUpscaleOptions o = series_method(m);
      const int steps = scale_time_axis(in[3], T, o);
      CHECK(steps == static_cast<int>(std::floor(4 * T + 1e-9)) + 1);  // 11, 10, 3: as sequences count frames
      CHECK(o.last_axis.scale == T);
      const Volume out = upscale_volume(v, {10, 7, 11, steps}, o);
      CHECK(worst_linear4_error(out, in, m == "tricubic-linear" ? 2.0 : 0.0, T) < 3e-6);
    }
  // A whole scale keeps the steps' arithmetic (no window), and cell-centred time rounds n * T.
  VolumeUpscaleOptions whole = series_method("ddt");
  CHECK(scale_time_axis(5, 3, whole) == 13);
  CHECK(whole.last_axis.scale == 0);
  VolumeUpscaleOptions cells = series_method("ddt");
  cells.node_centred[3] = false;
  CHECK(scale_time_axis(5, 2.5, cells) == 13);
  CHECK(cells.last_axis.scale == 0);
}

TEST_CASE("upscale_volume (series): input samples kept bit for bit at x3 in space, node-centred time x2 and x3") {
  const std::array<int, 4> in{4, 3, 4, 5};
  const Volume v = random_series(in, 7, 2);
  for (const int s : {2, 3})
    for (const Render render : {Render::cubic, Render::linear}) {
      CAPTURE(s);
      CAPTURE(to_string(render));
      VolumeUpscaleStats st;
      const Volume o = upscale_volume(v, {12, 9, 12, (in[3] - 1) * s + 1}, series_method("ddt", render), &st);
      CHECK(st.flips.total() > 0);
      int mismatches = 0;
      for (int t = 0; t < in[3]; ++t)
        for (int z = 0; z < in[2]; ++z)
          for (int y = 0; y < in[1]; ++y)
            for (int x = 0; x < in[0]; ++x)
              for (int c = 0; c < 2; ++c)
                mismatches += o.at4(3 * x + 1, 3 * y + 1, 3 * z + 1, s * t, c) != v.at4(x, y, z, t, c);
      CHECK(mismatches == 0);
    }
  // The classic methods keep them too (interpolating kernels, node-centred time).
  const Volume q = upscale_volume(volume_channel(v, 0), {12, 9, 12, 9}, series_method("quadrilinear"));
  double worst = 0;
  for (int t = 0; t < in[3]; ++t)
    for (int x = 0; x < in[0]; ++x)
      worst = std::max(worst, double(std::abs(q.at4(3 * x + 1, 4, 7, 2 * t) - v.at4(x, 1, 2, t, 0))));
  CHECK(worst < 1e-6);
}

TEST_CASE("upscale_volume (series): the same output bits for 1 and 2 threads, in slabs of time steps") {
  const Volume v = sample_series_field(find_volume_series_field("moving-sphere"), {8, 8, 8, 8}, 2);
  VolumeUpscaleOptions o = series_method("ddt");
  o.region_slices = 3;  // slabs of 3 time steps: several bands, phases in parallel
  Volume one, two;
  VolumeUpscaleStats st1, st2;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = upscale_volume(v, {16, 16, 16, 15}, o, &st1);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = upscale_volume(v, {16, 16, 16, 15}, o, &st2);
  }
  CHECK(st1.flips.total() > 0);
  CHECK(st1.flips.by_kind == st2.flips.by_kind);
  CHECK(one.voxels == two.voxels);
  CHECK(volume_region_slices({32, 32, 32, 16}) == 16);  // 715k simplices a step: at least 16 steps a slab
  CHECK(volume_region_slices({8, 8, 8, 8}) == 8);       // small: one region
}

TEST_CASE("upscale_volume (series): DDT beats quadrilinear on the moving sphere (small case)") {
  VolumeSeriesExperimentOptions o;
  o.size = 10;
  o.steps = 6;
  o.methods = {"quadrilinear", "ddt"};
  const auto all = run_volume_series_experiment(o);
  REQUIRE(all.size() == 3);  // the reference's isosurface first
  const auto& reference = all[0];
  const std::vector<VolumeSeriesExperimentRow> rows(all.begin() + 1, all.end());
  MESSAGE("moving sphere 10^3 x 6, x2 x4: quadrilinear " << rows[0].psnr << " dB, ddt " << rows[1].psnr << " dB");
  CHECK(rows[1].flips > 0);
  CHECK(rows[1].psnr > rows[0].psnr + 1.0);
  CHECK(rows[1].psnr_made > rows[0].psnr_made);
  // The isosurface is scored on the made steps: the count of true
  // crossings is the same for every row, the floor's surface the closest.
  CHECK(reference.iso_true_crossings > 0);
  for (const auto& r : rows) {
    CHECK(r.iso_true_crossings == reference.iso_true_crossings);
    CHECK(r.iso_crossings > r.iso_true_crossings / 2);
    CHECK(r.iso_rms > reference.iso_rms);
  }
}

TEST_CASE("upscale_volume (series): DDT beats quadrilinear on the box, the turning bar and the smooth blob (small)") {
  // 10^3 x 6: the shapes are a few voxels across, so the margins are
  // smaller than at 32^3 x 16 (docs/volumes.md, "Other scenes").
  for (const char* field : {"moving-box", "spinning-bar", "moving-blob"}) {
    CAPTURE(field);
    VolumeSeriesExperimentOptions o;
    o.field = field;
    o.size = 10;
    o.steps = 6;
    o.methods = {"quadrilinear", "ddt"};
    const auto all = run_volume_series_experiment(o);
    REQUIRE(all.size() == 3);
    const auto &quadrilinear = all[1], &ddt = all[2];
    MESSAGE(field << " 10^3 x 6, x2 x4: quadrilinear " << quadrilinear.psnr << " dB, ddt " << ddt.psnr << " dB");
    CHECK(ddt.flips > 0);
    CHECK(ddt.psnr > quadrilinear.psnr + 0.3);
    CHECK(ddt.psnr_made > quadrilinear.psnr_made + 0.3);
  }
}

TEST_CASE("upscale_volume (series): axes of one sample are dropped and the result repeated along them") {
  // x, y and t: the same as the 3D problem x, y, z with z node-centred.
  const Volume flat = random_series({5, 4, 1, 5}, 11);
  const Volume o = upscale_volume(flat, {10, 8, 3, 9}, series_method("ddt"));
  Volume as3d(5, 4, 5);
  as3d.voxels = flat.voxels;
  VolumeUpscaleOptions o3 = series_method("ddt");
  o3.node_centred = {false, false, true, false};
  const Volume r = upscale_volume(as3d, 10, 8, 9, o3);
  int mismatches = 0;
  for (int t = 0; t < 9; ++t)
    for (int z = 0; z < 3; ++z)
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 10; ++x) mismatches += o.at4(x, y, z, t) != r.at(x, y, t);
  CHECK(mismatches == 0);
  // A 3D volume asked for several steps: repeated along t.
  const Volume v3 = random_series({4, 4, 4, 1}, 12);
  const Volume rep = upscale_volume(v3, {8, 8, 8, 3}, series_method("ddt"));
  const Volume once = upscale_volume(v3, 8, 8, 8, series_method("ddt"));
  CHECK(std::equal(once.voxels.begin(), once.voxels.end(), rep.voxels.begin() + 2 * once.voxels.size()));
}

TEST_CASE("upscale_volume (series): bad arguments are refused with one line") {
  const Volume v = random_series({3, 3, 3, 3}, 1);
  CHECK_THROWS_WITH_AS(upscale_volume(v, {6, 6, 6, 5}, series_method("lanczos")),
                       doctest::Contains("quadrilinear"), Error);
  CHECK_THROWS_AS(upscale_volume(v, {6, 6, 6, 0}, series_method("ddt")), Error);
  CHECK_THROWS_AS(upscale_volume(Volume(3, 3, 3), 6, 6, 6, series_method("quadrilinear")), Error);  // 3D: no
  Volume broken = v;
  broken.nt = 4;  // samples do not match the size
  CHECK_THROWS_AS(upscale_volume(broken, {6, 6, 6, 7}, series_method("ddt")), Error);
  CHECK(enlarged_size(16, 4, true) == 61);
  CHECK(enlarged_size(16, 4, false) == 64);
  CHECK(enlarged_size(1, 4, true) == 4);
  CHECK(enlarged_size(32, 2.5, false) == 80);
}

TEST_CASE("sample_series_field and pictures: instants at l / (n - 1), the x-t plane shows the motion") {
  const VolumeSeriesField& f = find_volume_series_field("moving-sphere");
  const Volume v = sample_series_field(f, {16, 16, 16, 5}, 2);
  // At t = 0 the ball is centred at x = 0.3, at t = 1 at x = 0.7.
  CHECK(v.at4(4, 7, 8, 0) > 0.9f);
  CHECK(v.at4(11, 8, 8, 0) < 0.1f);
  CHECK(v.at4(11, 8, 8, 4) > 0.9f);
  const Image xt = series_xt_view(v);
  CHECK(xt.width == 16);
  CHECK(xt.height == 5);
  const Image pic = compare_series_views({&v, &v}, 2, {VolumeView::slice_xy}, 0.0, 1.0);
  CHECK(pic.width == 4 + 2 * (16 + 4));
  CHECK(pic.height == 4 + 16 + 4 + 5 + 4);
  CHECK_THROWS_AS(find_volume_series_field("nope"), Error);
}
