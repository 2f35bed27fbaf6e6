#include "image/image_mesh.hpp"

namespace ddt {

int optimizer_region_rows(int width, int height, const UpscaleOptions& options) {
  if (width < 2 || height < 2 || options.region_rows < 0) return 0;
  if (options.region_rows > 0) return options.region_rows;
  const long long cells_row = 2LL * (width - 1);
  const long long triangles = cells_row * (height - 1);
  if (triangles <= 2 * default_region_triangles) return 0;
  return static_cast<int>(image_region_triangles(width) / cells_row);
}

std::vector<Point2> pixel_centres(int width, int height) {
  std::vector<Point2> points(static_cast<std::size_t>(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) points[static_cast<std::size_t>(y) * width + x] = {x + 0.5, y + 0.5};
  return points;
}

Mesh2 image_mesh(const Image& src, const UpscaleOptions& options, UpscaleStats* stats) {
  UpscaleOptions quiet = options;
  quiet.progress = nullptr;
  return upscale_mesh(src, quiet, stats);
}

}  // namespace ddt
