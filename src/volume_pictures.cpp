#include "volume_pictures.hpp"

#include "error.hpp"

#include <algorithm>
#include <cmath>

namespace ddt {

const char* view_name(VolumeView view) {
  switch (view) {
    case VolumeView::slice_xy: return "middle x-y slice";
    case VolumeView::slice_xz: return "middle x-z slice";
    case VolumeView::slice_yz: return "middle y-z slice";
    case VolumeView::mip_z: return "maximum-intensity projection along z";
  }
  return "?";
}

Image volume_view(const Volume& v, VolumeView view) {
  switch (view) {
    case VolumeView::slice_xy: {
      Image img(v.nx, v.ny, 1);
      for (int y = 0; y < v.ny; ++y)
        for (int x = 0; x < v.nx; ++x) img.at(x, y) = v.at(x, y, v.nz / 2);
      return img;
    }
    case VolumeView::slice_xz: {
      Image img(v.nx, v.nz, 1);
      for (int z = 0; z < v.nz; ++z)
        for (int x = 0; x < v.nx; ++x) img.at(x, z) = v.at(x, v.ny / 2, z);
      return img;
    }
    case VolumeView::slice_yz: {
      Image img(v.ny, v.nz, 1);
      for (int z = 0; z < v.nz; ++z)
        for (int y = 0; y < v.ny; ++y) img.at(y, z) = v.at(v.nx / 2, y, z);
      return img;
    }
    case VolumeView::mip_z: {
      Image img(v.nx, v.ny, 1, -HUGE_VALF);
      for (int z = 0; z < v.nz; ++z)
        for (int y = 0; y < v.ny; ++y)
          for (int x = 0; x < v.nx; ++x) img.at(x, y) = std::max(img.at(x, y), v.at(x, y, z));
      return img;
    }
  }
  return {};
}

void value_range(const Volume& v, double& lo, double& hi) {
  if (v.empty()) throw Error("value_range: the volume is empty");
  const auto [mn, mx] = std::minmax_element(v.voxels.begin(), v.voxels.end());
  lo = *mn;
  hi = *mx;
}

Image compare_views(const std::vector<const Volume*>& volumes, const std::vector<VolumeView>& views, double lo,
                    double hi) {
  if (volumes.empty() || views.empty()) throw Error("compare_views: nothing to show");
  for (const Volume* v : volumes)
    if (v->nx != volumes[0]->nx || v->ny != volumes[0]->ny || v->nz != volumes[0]->nz)
      throw Error("compare_views: the volumes differ in size");
  constexpr int gap = 4;
  std::vector<int> row_height, row_top;
  int cell_width = 0, height = gap;
  for (VolumeView view : views) {
    const Image probe = volume_view(*volumes[0], view);
    cell_width = std::max(cell_width, probe.width);
    row_top.push_back(height);
    row_height.push_back(probe.height);
    height += probe.height + gap;
  }
  const int columns = static_cast<int>(volumes.size());
  Image out(gap + columns * (cell_width + gap), height, 1, 0.1f);
  const double span = hi > lo ? hi - lo : 1.0;
  for (int c = 0; c < columns; ++c)
    for (std::size_t r = 0; r < views.size(); ++r) {
      const Image cell = volume_view(*volumes[c], views[r]);
      const int left = gap + c * (cell_width + gap);
      for (int y = 0; y < cell.height; ++y)
        for (int x = 0; x < cell.width; ++x)
          out.at(left + x, row_top[r] + y) = static_cast<float>(std::clamp((cell.at(x, y) - lo) / span, 0.0, 1.0));
    }
  return out;
}

}  // namespace ddt
