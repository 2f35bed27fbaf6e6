#pragma once
// The classic separable resamplers for volumes: the baselines DDT is
// compared with (classic_resize.hpp's twin).
//
//   "trilinear"  the 8-neighbour interpolant, written here (it is two lines
//                of arithmetic); cross-checked in the tests against Teem's
//                tent kernel
//   "tricubic"   separable Catmull-Rom (Keys, a = -0.5) by Teem's nrrd
//                resampler (nrrdKernelCatmullRom), the tricubic of the
//                visualization literature; it overshoots at edges
//
// Both follow the voxel convention of volume.hpp: output voxel X samples the
// input at (X + 0.5) / s, i.e. index position (X + 0.5) / s - 0.5. Outside
// the samples' hull the index is clamped (Teem: "bleed" boundary), the
// same nearest-hull-point rule DDT's rasterizer uses.
//
// Inputs:  src non-empty; nx, ny, nz >= 1; method "trilinear" or "tricubic"
// Output:  nx x ny x nz volume (not clamped to the input's range)
// Errors:  ddt::Error for an unknown method (listing the valid ones), an
//          empty source, a bad size, or a Teem failure.

#include "volume/volume.hpp"

#include <array>
#include <string>
#include <vector>

namespace ddt {

Volume classic_resize_volume(const Volume& src, int nx, int ny, int nz, const std::string& method);

// Teem's separable resampler with a named kernel: "tent" (linear) or
// "catmull-rom". Exposed for the cross-check of "trilinear".
Volume teem_resample(const Volume& src, int nx, int ny, int nz, const std::string& kernel);

// The classic resamplers of volume series (4D, one channel; any nt >= 1),
// through Teem's resampler with a kernel per axis:
//   "quadrilinear"      tent on all four axes (linear in space and time)
//   "tricubic-linear"   Catmull-Rom in space, tent in time
// and a centring per axis: node_centred axes (time: steps are instants)
// put output sample 0 on input sample 0 and the last on the last (Teem's
// node centring), the others follow the voxel convention (cell centring).
// Indices are clamped outside the samples (bleed), as in 3D. A 3D volume
// (nt = 1) with "trilinear" or "tricubic" takes this path too when one of
// its axes is node-centred.
// `window`, when its scale is > 0: along its axis, output sample j is sample
// first + j of the grid of that scale aligned with the input as above
// (node-centred: at input position (first + j) / scale), what the mesh
// methods' VolumeUpscaleOptions::last_axis gives (fractional time scales).
struct AxisWindow {
  int axis = 3;
  double scale = 0, first = 0;
};
Volume classic_resize_axes(const Volume& src, const std::array<int, 4>& size, const std::string& method,
                           const std::array<bool, 4>& node_centred, const AxisWindow& window = {});

}  // namespace ddt
