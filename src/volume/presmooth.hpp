#pragma once
// ddt::smoothed_grid — Gaussian smoothing of a grid of samples along chosen
// axes, by Teem's nrrd resampler (nrrdKernelGaussian, cut at 3 sigma,
// "bleed" boundary: the edge samples repeat; renormalized weights), at
// the same size. What the graduated optimization (volume_upscale.hpp,
// `presmooth`) optimizes on first.
//
// values: channels fastest, then axis 0, 1, ... (size.size() axes, 1 to 4).
// sigma: per axis, in samples; 0 leaves that axis alone.
// Errors: ddt::Error on bad sizes or a Teem failure.

#include <vector>

namespace ddt {

std::vector<float> smoothed_grid(const std::vector<float>& values, const std::vector<int>& size, int channels,
                                 const std::vector<double>& sigma);

}  // namespace ddt
