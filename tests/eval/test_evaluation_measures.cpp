// Tests for the synthetic measures of evaluation.hpp (halo, edge
// sharpness) and their CSV columns.

#include "eval/evaluation.hpp"

#include "eval/synthetic_scenes.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;
using ddt::EvalRow;

TEST_CASE("evaluate_synthetic: halo on every scene, edge sharpness on the step edges only") {
  ddt::EvalOptions options;
  options.scales = {4};
  options.synthetic_size = 32;
  options.methods = ddt::make_eval_methods({"nearest", "lanczos"}, {}, {});
  const auto rows = ddt::evaluate_synthetic(options);
  const auto scenes = ddt::standard_scenes();
  REQUIRE(rows.size() == 2 * scenes.size());
  int edges = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ddt::Scene& scene = scenes[i / 2];
    const EvalRow& r = rows[i];
    CAPTURE(r.image);
    CAPTURE(r.method);
    CHECK(std::isfinite(r.halo));
    CHECK(r.halo >= 0.0);
    CHECK(scene.step_edge.has_value() == (scene.name.rfind("edge_", 0) == 0));
    if (!scene.step_edge) {
      CHECK(std::isnan(r.rise_width));
      CHECK(std::isnan(r.overshoot));
      continue;
    }
    ++edges;
    CHECK(r.rise_width > 0.3);  // blurred by any interpolation of box averages
    CHECK(r.rise_width < 2.0);
    CHECK(r.wobble + 1e-12 >= std::abs(r.edge_offset));  // equal for a straight, shifted edge
    if (r.method == "nearest") {
      CHECK(r.halo < 0.01);  // percent: replication stays in the truth's range
      CHECK(r.overshoot < 0.01);
    } else {
      CHECK(r.halo > 1.0);  // Lanczos-3 rings beside every edge
      CHECK(r.overshoot > 1.0);
    }
  }
  CHECK(edges == 2 * 5);
  const auto summary = ddt::edge_summary_by_method_and_scale(rows);
  REQUIRE(summary.size() == 2);
  CHECK(summary[0].method == "nearest");
  CHECK(summary[0].edges == 5);
  CHECK(summary[1].overshoot_max > 1.0);
  CHECK(summary[1].rise_width_max >= summary[1].rise_width);
  CHECK(summary[0].wobble > summary[1].wobble);  // replication is a staircase
}

TEST_CASE("write_eval_csv: the synthetic columns, empty where a measure was not taken") {
  const fs::path csv = fs::temp_directory_path() / ("ddtscale_measures_" + std::to_string(::getpid()) + ".csv");
  EvalRow edge{"edge_30", 4, "lanczos", 30.5, 0.95, 0.5};
  edge.halo = 6.5;
  edge.rise_width = 1.0;
  edge.wobble = 0.02;
  edge.edge_offset = -0.01;
  edge.overshoot = 7.25;
  EvalRow disk{"disk", 4, "lanczos", 28.0, 0.9, 0.25};
  disk.halo = 5.0;
  ddt::write_eval_csv(csv.string(), {edge, disk}, /*synthetic_columns=*/true);
  std::ifstream in(csv);
  std::stringstream text;
  text << in.rdbuf();
  fs::remove(csv);
  CHECK(text.str() ==
        "image,scale,method,psnr,ssim,seconds,halo,rise_width,wobble,edge_offset,overshoot\n"
        "edge_30,4,lanczos,30.500000,0.950000,0.500000,6.500000,1.000000,0.020000,-0.010000,7.250000\n"
        "disk,4,lanczos,28.000000,0.900000,0.250000,5.000000,,,,\n");
}
