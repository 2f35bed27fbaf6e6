#pragma once
// ddt::image_mesh — the optimized DDT mesh of an image: one vertex per
// pixel centre (vertex id y * width + x at (x + 0.5, y + 0.5)), the CGAL
// Delaunay triangulation, then the flips that `options` asks for. The mesh
// upscale() renders (untiled), exposed for the mesh view and tools.
//
// Also the pieces upscale() shares with it: the channels that drive the
// flips (the colour channels, all but options.alpha_channel, or their
// Rec. 601 luminance when options.luma_cost) and the optimizer's region
// rows.

#include "core/costs.hpp"
#include "util/image.hpp"
#include "image/mesh.hpp"
#include "image/optimizer.hpp"
#include "pipeline/upscale.hpp"

#include <vector>

namespace ddt {

// Which channels of an image drive the flips, and how.
struct DriveChannels {
  std::vector<int> colour;  // the image's channels that count
  bool luma = false;        // one drive value: their luminance
  int K = 0;                // drive values per pixel
  bool identity = false;    // the drive values are the pixels themselves
};

// Throws ddt::Error when there are more colour channels than a cost takes.
DriveChannels drive_channels(const Image& src, const UpscaleOptions& options);

// Drive values of n pixels of C channels: n by d.K, row-major.
std::vector<float> drive_values(const float* pixels, std::size_t n, int C, const DriveChannels& d);

// Rows of input pixels per region of the parallel optimizer (0: a single
// region), as options.region_rows asks for an image of width x height.
int optimizer_region_rows(int width, int height, const UpscaleOptions& options);

// Pixel centres of a width x height grid, row-major.
std::vector<Point2> pixel_centres(int width, int height);

// Throws ddt::Error for an empty image, an unknown cost or optimizer.
Mesh2 image_mesh(const Image& src, const UpscaleOptions& options = {}, UpscaleStats* stats = nullptr);

}  // namespace ddt
