#pragma once
// Analytic test volumes for the paper's 3D experiments (Sect. 5, Figs. 9
// and 10): fields known exactly at every resolution, so an enlargement can
// be scored against the true high-resolution volume (synthetic_scenes.hpp's
// twin).
//
// A field is a function on the unit cube [0,1]^3 (x, y, z), values in 0..1.
// Sampling at nx x ny x nz box-filters it: voxel (i, j, k) is the mean of
// ss^3 point samples spread evenly over [i/nx, (i+1)/nx] x ... , the
// footprint of a scanner's voxel. This agrees with the voxel convention of
// volume.hpp: sample (i, j, k) sits at ((i + 0.5) / nx, ...).
//
// The fields:
//   sphere    the paper's "sphere embedded into a cube": a solid ball of
//             radius 0.35 (11.2 voxels at 32^3) centred in the cube, 1
//             inside and 0 outside; box-filtered, its surface is a
//             partial-volume shell one voxel thick
//   hydrogen  the probability density of the hydrogen 3d_z2 orbital
//             (n = 3, l = 2, m = 0): |psi|^2 proportional to
//             r^4 exp(-2r/3) (3 cos^2(theta) - 1)^2, r in Bohr radii, the
//             cube spanning [-20, 20]^3 a0, scaled to a maximum of 1 (two
//             lobes on the z axis, peak at r = 6, and a torus in the
//             x-y plane at a quarter of the peak)
//
// Errors: functions throw ddt::Error (unknown field name, bad size).

#include "volume/volume.hpp"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace ddt {

struct VolumeField {
  std::string name;
  std::string description;
  std::function<double(double x, double y, double z)> value;  // on [0,1]^3
  double iso_level = 0.5;  // a level whose isosurface shows the field's shape
};

const std::vector<VolumeField>& volume_fields();  // sphere, hydrogen
const VolumeField& find_volume_field(const std::string& name);
std::string volume_field_names();  // "sphere, hydrogen", for messages and --help

// Box-filtered sampling as above; ss >= 1 point samples per axis per voxel
// (ss = 1: point samples at the voxel centres). Parallel over slices.
Volume sample_field(const VolumeField& field, int nx, int ny, int nz, int ss);

// Volume series (4D) with known truth: a field on [0,1]^3 x [0,1] (x, y, z,
// t), values in 0..1. Sampling at nx x ny x nz x nt box-filters space as
// above and samples time at instants, step l at t = l / (nt - 1) (the time
// axis is node-centred: the first and last steps are t = 0 and t = 1; one
// step is t = 0), the convention of volume_upscale.hpp, so a series
// enlarged from n to (n - 1) s + 1 steps is compared with the field at the
// same instants.
//
//   moving-sphere   a solid ball, 1 inside and 0 outside, whose centre
//                   moves from (0.3, 0.45, 0.5) to (0.7, 0.55, 0.5) and
//                   whose radius grows from 0.15 to 0.25 as t goes from 0
//                   to 1 (at 32^3 x 16 steps: 0.85 voxel along x and 0.21
//                   voxel of radius per step)
//   moving-box      a solid box, half-extents (0.16, 0.12, 0.14), whose
//                   centre moves from (0.3, 0.35, 0.4) to (0.65, 0.6, 0.55):
//                   flat faces, edges and corners crossing every axis
//   spinning-bar    a solid bar, half-extents (0.32, 0.07, 0.2), centred,
//                   turning 1 radian about z: each point at its own speed
//   moving-blob     a Gaussian, sigma 0.1, peak 1, centre (0.35, 0.4, 0.45)
//                   -> (0.65, 0.6, 0.55): smooth, no edge (level 0.5)
// The three after the sphere check the 4D method's claims away from the
// scene they were made on (docs/volumes.md, "Other scenes").
struct VolumeSeriesField {
  std::string name;
  std::string description;
  std::function<double(double x, double y, double z, double t)> value;
  double iso_level = 0.5;
  // Signed distance to the true surface of iso_level (negative inside),
  // for isosurface_error.hpp; null when not known.
  std::function<double(double x, double y, double z, double t)> surface_distance;
};

const std::vector<VolumeSeriesField>& volume_series_fields();  // moving-sphere, then the others above
const VolumeSeriesField& find_volume_series_field(const std::string& name);
std::string volume_series_field_names();  // "moving-sphere, moving-box, ...", for messages and --help
Volume sample_series_field(const VolumeSeriesField& field, const std::array<int, 4>& size, int ss);

// Root-mean-square difference over all voxels (of every time step);
// PSNR = 20 log10(peak / RMSE) in dB (+infinity when equal). Volumes must
// have the same size.
double volume_rmse(const Volume& a, const Volume& b);
double volume_psnr(const Volume& a, const Volume& b, double peak = 1.0);

}  // namespace ddt
