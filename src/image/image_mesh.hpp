#pragma once
// ddt::image_mesh — the optimized DDT mesh of an image: one vertex per
// pixel centre (vertex id y * width + x at (x + 0.5, y + 0.5)), the CGAL
// Delaunay triangulation, then the flips that `options` asks for. The mesh
// upscale() renders (untiled), exposed for the mesh view and tools: it is
// the mesh stage of upscale's pipeline (upscale_mesh), not a copy of it.
//
// Also the optimizer's region rows, and (drive_channels.hpp) the channels
// that drive the flips.

#include "core/costs.hpp"
#include "util/image.hpp"
#include "image/mesh.hpp"
#include "image/optimizer.hpp"
#include "pipeline/drive_channels.hpp"
#include "pipeline/upscale.hpp"

#include <vector>

namespace ddt {

// Rows of input pixels per region of the parallel optimizer (0: a single
// region), as options.region_rows asks for an image of width x height.
int optimizer_region_rows(int width, int height, const UpscaleOptions& options);

// Pixel centres of a width x height grid, row-major.
std::vector<Point2> pixel_centres(int width, int height);

// Throws ddt::Error for an empty image, an unknown cost or optimizer. The
// progress is not told (the mesh view runs after the enlargement).
Mesh2 image_mesh(const Image& src, const UpscaleOptions& options = {}, UpscaleStats* stats = nullptr);

}  // namespace ddt
