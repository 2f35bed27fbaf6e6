#include "pipeline/drive_channels.hpp"

#include "core/costs.hpp"
#include "image/optimizer.hpp"
#include "util/error.hpp"

#include <string>

namespace ddt {

DriveChannels drive_channels(const Image& src, const UpscaleOptions& options) {
  return drive_channels(src.channels, options);
}

DriveChannels drive_channels(int channels, const UpscaleOptions& options) {
  DriveChannels d;
  for (int c = 0; c < channels; ++c)
    if (c != options.alpha_channel) d.colour.push_back(c);
  if (options.luma_cost && d.colour.size() >= 3) {
    d.luma = true;
    d.K = 1;
    return d;
  }
  if (d.colour.size() > static_cast<std::size_t>(max_cost_channels))
    throw Error("the cost takes at most " + std::to_string(max_cost_channels) + " channels; this image has " +
                std::to_string(d.colour.size()) + " (use --cost-channel luma)");
  if (d.colour.empty()) d.colour.push_back(0);  // alpha alone: let it drive
  d.K = static_cast<int>(d.colour.size());
  d.identity = d.K == channels;
  return d;
}

std::vector<float> drive_values(const float* pixels, std::size_t n, int C, const DriveChannels& d) {
  std::vector<float> out(n * d.K);
  const std::vector<int>& colour = d.colour;
  if (d.luma) {
    for (std::size_t i = 0; i < n; ++i) {
      const float* px = pixels + i * C;
      out[i] = luma_601(px[colour[0]], px[colour[1]], px[colour[2]]);
    }
    return out;
  }
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < d.K; ++k) out[i * d.K + k] = pixels[i * C + colour[k]];
  return out;
}

}  // namespace ddt
