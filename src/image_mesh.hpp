#pragma once
// ddt::image_mesh — the optimized DDT mesh of an image: one vertex per
// pixel centre (vertex id y * width + x at (x + 0.5, y + 0.5)), the CGAL
// Delaunay triangulation, then the flips that `options` asks for. The mesh
// upscale() renders, exposed for the mesh view and tools.
//
// Also the channels that drive the flips (cost_channel_values): the colour
// channels (all but options.alpha_channel), or their Rec. 601 luminance
// when options.luma_cost.

#include "image.hpp"
#include "mesh.hpp"
#include "upscale.hpp"

#include <vector>

namespace ddt {

// Outputs: values #pixels by K, row-major; K set to the channel count.
std::vector<float> cost_channel_values(const Image& src, const UpscaleOptions& options, int& K);

// Pixel centres of a width x height grid, row-major.
std::vector<Point2> pixel_centres(int width, int height);

// Throws ddt::Error for an empty image or an unknown cost.
Mesh2 image_mesh(const Image& src, const UpscaleOptions& options = {}, UpscaleStats* stats = nullptr);

}  // namespace ddt
