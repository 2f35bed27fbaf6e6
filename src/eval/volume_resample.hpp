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
// Inputs:  src non-empty; nx, ny, nz >= 1; method one of volume_methods()
// Output:  nx x ny x nz volume (not clamped to the input's range)
// Errors:  ddt::Error for an unknown method (listing the valid ones), an
//          empty source, a bad size, or a Teem failure.

#include "volume/volume.hpp"

#include <string>
#include <vector>

namespace ddt {

const std::vector<std::string>& volume_methods();  // {"trilinear", "tricubic"}

Volume classic_resize_volume(const Volume& src, int nx, int ny, int nz, const std::string& method);

// Teem's separable resampler with a named kernel: "tent" (linear) or
// "catmull-rom". Exposed for the cross-check of "trilinear".
Volume teem_resample(const Volume& src, int nx, int ny, int nz, const std::string& kernel);

}  // namespace ddt
