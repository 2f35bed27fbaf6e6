#pragma once
// ddt::DriveChannels — which channels of the samples drive the flips, and
// how: the colour channels (all but the alpha channel), one of them, or
// their Rec. 601 luminance. Written once for images (UpscaleOptions) and
// scattered points (GridOptions::cost_channel); the values themselves are
// interpolated on the mesh whatever drives it.

#include "pipeline/upscale.hpp"
#include "util/image.hpp"

#include <cstddef>
#include <vector>

namespace ddt {

struct DriveChannels {
  std::vector<int> colour;  // the channels that count
  bool luma = false;        // one drive value: the luminance of colour[0..2]
  int K = 0;                // drive values per sample
  bool identity = false;    // the drive values are the samples themselves
};

// Rec. 601 luma weights, as the evaluation's Y.
inline float luma_601(float r, float g, float b) { return 0.299f * r + 0.587f * g + 0.114f * b; }

// An image's: the colour channels, all but options.alpha_channel (alpha
// alone drives when it is the only channel), or their luminance when
// options.luma_cost and there are three or more.
// Throws ddt::Error when there are more colour channels than a cost takes.
DriveChannels drive_channels(const Image& src, const UpscaleOptions& options);
DriveChannels drive_channels(int channels, const UpscaleOptions& options);

// Drive values of n samples of C channels: n by d.K, row-major.
std::vector<float> drive_values(const float* pixels, std::size_t n, int C, const DriveChannels& d);

}  // namespace ddt
