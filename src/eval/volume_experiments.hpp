#pragma once
// The paper's 3D experiments (Sect. 5, Figs. 9 and 10), reproduced and
// scored: each analytic field (volume_fields.hpp) is sampled at size^3,
// enlarged by `scale` with every method, and compared with the same field
// sampled at the high resolution (size * scale)^3: RMSE and PSNR (peak 1,
// the fields' range).
//
// Sampling: the input is box-filtered with input_ss^3 point samples per
// voxel, the reference with reference_ss^3 per (smaller) voxel; both are
// the footprint of a scanner's voxel at their resolution.
//
// Quantization (quantize_bits = b > 0): the input samples are rounded to
// b bits, v -> round(v (2^b - 1)) / (2^b - 1), as an 8-bit data set stores
// the field (the paper's hydrogen volume); the reference stays continuous.
// Pictures are then named <field>-x<scale>-q<b>.png (and -q<b>-iso.png).
//
// Methods are volume_upscale_methods() names; "ddt:COST" picks the cost
// (plain "ddt" is "ddt:variance", the paper's choice for its figures).
//
// Pictures (when picture_dir is set): <dir>/<field>-x<scale>.png, one
// column per picture_methods entry after the reference, rows: middle x-y
// slice, middle x-z slice, maximum-intensity projection along z; grey
// levels 0..1. And <dir>/<field>-x<scale>-iso.png, the same columns as
// shaded isosurfaces at the field's iso_level or options.iso_level
// (volume_pictures.hpp), each
// 2 * size * scale pixels square.
//
// Errors: throws ddt::Error (unknown field, method or cost; unwritable
// directory).

#include "volume/volume_upscale.hpp"

#include <functional>
#include <string>
#include <vector>

namespace ddt {

struct VolumeExperimentOptions {
  int size = 32;
  int scale = 4;
  int input_ss = 8;
  int reference_ss = 6;
  int quantize_bits = 0;  // 0: the input keeps float precision
  double iso_level = 0;   // > 0: the isosurface pictures' level instead of the field's iso_level
  std::vector<std::string> fields = {"sphere", "hydrogen"};
  std::vector<std::string> methods = {"trilinear", "tricubic", "delaunay", "ddt-linear:variance", "ddt:variance",
                                      "ddt:sederberg"};
  std::vector<std::string> picture_methods = {"trilinear", "ddt-linear:variance", "ddt:variance"};
  std::string picture_dir;  // empty: no pictures
  std::function<void(const std::string&)> log;
};

struct VolumeExperimentRow {
  std::string field;
  std::string method;
  double rmse = 0;
  double psnr = 0;
  double seconds = 0;
  long long flips = 0;
};

std::vector<VolumeExperimentRow> run_volume_experiments(const VolumeExperimentOptions& options);

// A method of the experiments' lists: "ddt" (cost variance), "ddt:COST",
// "ddt-linear" and "delaunay-linear" (the paper's linear render; "-cubic":
// the default, named), or a classic method's name. Throws ddt::Error on an
// unknown method.
VolumeUpscaleOptions volume_options_for(const std::string& spec);

// The rows as a Markdown table (field, method, RMSE, PSNR, flips, seconds).
std::string volume_experiment_table(const std::vector<VolumeExperimentRow>& rows);

}  // namespace ddt
