#pragma once
// The volume-series experiment (4D, known truth): a series field
// (volume_fields.hpp: moving-sphere by default) sampled at size^3 x steps, enlarged by
// `scale` in space and `time_scale` in time (node-centred time: steps
// become (steps - 1) * time_scale + 1, every input step kept), and compared
// with the field sampled at the output's size and instants: RMSE and PSNR
// (peak 1) over all samples of all steps, and over the made steps only
// (those between input steps, where time is really interpolated). And,
// for a field with a known surface, how far each method's isosurface of the
// field's level lies from the true one over the made steps
// (isosurface_error.hpp: RMS and 99th percentile in output voxels, and the
// crossings found against the true count); then the first row is the
// field itself sampled as the output is (the metric's floor; no RMSE).
//
// Sampling as the 3D experiments (volume_experiments.hpp): space is
// box-filtered, input_ss^3 point samples per input voxel and reference_ss^3
// per output voxel; time is point-sampled (the steps are instants).
//
// Methods: volume_series_upscale_methods() names, "ddt:COST" picks the cost
// (plain "ddt" is "ddt:variance"); "ddt-linear", "delaunay-linear" the
// piecewise-linear render (the default is cubic); the ddt methods run the
// graduated optimization of the command line (presmooth_in_space(true)),
// "ddt-unsmoothed" without it.
//
// Pictures (picture_dir set): <dir>/<field>-x<scale>-t<time_scale>.png, one
// column per picture_methods entry after the reference; rows: the middle x-y
// slice of the middle output step (between two input steps when the time
// scale is even), and the x-t plane at the middle y and z. And
// <dir>/<field>-x<scale>-t<time_scale>-iso.png: the isosurfaces of that step.
//
// Errors: throws ddt::Error (unknown field, method or cost; bad sizes;
// missing directory).

#include <functional>
#include <string>
#include <vector>

namespace ddt {

struct VolumeSeriesExperimentOptions {
  std::string field = "moving-sphere";
  int size = 32;        // input voxels per spatial axis
  int steps = 16;       // input time steps
  int scale = 2;        // spatial magnification
  int time_scale = 4;   // temporal magnification (node-centred)
  int input_ss = 4;
  int reference_ss = 2;
  std::vector<std::string> methods = {"quadrilinear", "tricubic-linear", "delaunay", "ddt-linear", "ddt-unsmoothed",
                                      "ddt"};
  std::vector<std::string> picture_methods = {"quadrilinear", "tricubic-linear", "ddt"};
  std::string picture_dir;  // empty: no pictures
  std::function<void(const std::string&)> log;
};

struct VolumeSeriesExperimentRow {
  std::string field;
  std::string method;
  double rmse = 0;
  double psnr = 0;
  double psnr_made = 0;  // over the output steps between input steps
  // Isosurface of the field's level over the made steps (0 when the field
  // has no known surface).
  double iso_rms = 0, iso_p99 = 0;  // output voxels
  double iso_rms_kept = 0;           // the same over the kept (input) steps
  double iso_normal_rms = 0, iso_normal_p99 = 0;  // the shading normal's angle, made steps (degrees)
  long long iso_crossings = 0, iso_true_crossings = 0;
  double seconds = 0;
  long long flips = 0;
  long long simplices = 0;
};

std::vector<VolumeSeriesExperimentRow> run_volume_series_experiment(const VolumeSeriesExperimentOptions& options);

// The rows as a Markdown table.
std::string volume_series_experiment_table(const std::vector<VolumeSeriesExperimentRow>& rows);

}  // namespace ddt
