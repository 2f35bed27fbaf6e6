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

// Box-filtered sampling as above; ss >= 1 point samples per axis per voxel
// (ss = 1: point samples at the voxel centres). Parallel over slices.
Volume sample_field(const VolumeField& field, int nx, int ny, int nz, int ss);

// Root-mean-square difference over all voxels; PSNR = 20 log10(peak / RMSE)
// in dB (+infinity when equal). Volumes must have the same size.
double volume_rmse(const Volume& a, const Volume& b);
double volume_psnr(const Volume& a, const Volume& b, double peak = 1.0);

}  // namespace ddt
