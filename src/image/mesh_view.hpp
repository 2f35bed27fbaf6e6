#pragma once
// ddt::write_mesh_view — draws a triangulation over the image it was built
// on, as in the last column of the paper's figure 8, so the long thin
// triangles that follow edges are visible. The format follows the
// extension: .svg (vector edges over the embedded pixels) or any raster
// format (the pixels enlarged by nearest neighbour, edges drawn on top).
// Edges of the initial Delaunay mesh are drawn thin and light; edges the
// optimization created are drawn in orange.
//
// Inputs:
//   mesh      the optimized mesh of `image` (vertex per pixel centre)
//   initial   the mesh before the flips, or nullptr (then no highlighting)
//   image     the input image (any channel count; the first three are shown)
//   roi       region in input pixels; width 0 means the whole image
// Writes atomically; throws ddt::Error.

#include "util/image.hpp"
#include "image/mesh.hpp"
#include "image/pixel_region.hpp"

#include <string>

namespace ddt {


void write_mesh_view(const std::string& path, const Mesh2& mesh, const Mesh2* initial, const Image& image,
                     PixelRegion roi = {}, int magnification = 0);


}  // namespace ddt
