#pragma once
// ddt::Volume — the library's in-memory scalar volume: float samples,
// x fastest, then y, then z (NRRD's and most viewers' order).
//
// Voxel convention (the 3D form of image.hpp's pixel convention, used by
// every volume function in ddtscale): sample (i, j, k) sits at the voxel
// centre (i + 0.5, j + 0.5, k + 0.5) in continuous volume coordinates, so a
// volume of size nx covers [0, nx) and its samples span [0.5, nx - 0.5].
// An output voxel X of a volume enlarged by sx samples the input at
// (X + 0.5) / sx.
//
// Values are kept as stored (no rescaling of integer types), so a CT volume
// keeps its Hounsfield units and an 8-bit volume its 0..255.

#include <cstddef>
#include <vector>

namespace ddt {

struct Volume {
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> voxels;  // nx * ny * nz

  Volume() = default;
  Volume(int x, int y, int z, float fill = 0.0f)
      : nx(x), ny(y), nz(z), voxels(static_cast<std::size_t>(x) * y * z, fill) {}

  std::size_t voxel_count() const { return static_cast<std::size_t>(nx) * ny * nz; }
  bool empty() const { return voxels.empty(); }

  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * ny + y) * nx + x;
  }
  float& at(int x, int y, int z) { return voxels[index(x, y, z)]; }
  float at(int x, int y, int z) const { return voxels[index(x, y, z)]; }
};

}  // namespace ddt
