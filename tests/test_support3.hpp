#pragma once
// Small builders shared by the 3D tests.

#include "volume/volume.hpp"

namespace ddt::test {

// Volume whose voxel (x, y, z) holds f(x + 0.5, y + 0.5, z + 0.5).
template <class F>
Volume sampled_volume(int nx, int ny, int nz, F f) {
  Volume v(nx, ny, nz);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) v.at(x, y, z) = static_cast<float>(f(x + 0.5, y + 0.5, z + 0.5));
  return v;
}

}  // namespace ddt::test
