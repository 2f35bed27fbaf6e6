#pragma once
// ddt::Volume — the library's in-memory volume: float samples with C >= 1
// channels (1: scalar, 3: RGB or a 3-vector, ...), channels fastest, then x,
// then y, then z, then t (NRRD's order with the non-spatial axis first, and
// most viewers'). A 3D volume has nt = 1; a volume series (4D: x, y, z and
// time steps) has nt > 1.
//
// Voxel convention (the 3D form of image.hpp's pixel convention, used by
// every volume function in ddtscale): sample (i, j, k) sits at the voxel
// centre (i + 0.5, j + 0.5, k + 0.5) in continuous volume coordinates, so a
// volume of size nx covers [0, nx) and its samples span [0.5, nx - 0.5].
// An output voxel X of a volume enlarged by sx samples the input at
// (X + 0.5) / sx. Time steps are instants (node-centred, volume_upscale.hpp):
// step l sits at l + 0.5 too, and n steps enlarged by s become (n - 1) s + 1.
//
// Values are kept as stored (no rescaling of integer types), so a CT volume
// keeps its Hounsfield units and an 8-bit volume its 0..255.

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace ddt {

struct Volume {
  int nx = 0, ny = 0, nz = 0;
  int channels = 1;
  std::vector<float> voxels;  // nx * ny * nz * nt * channels
  int nt = 1;                 // time steps (4D); 1 for a 3D volume

  Volume() = default;
  Volume(int x, int y, int z, float fill = 0.0f)
      : nx(x), ny(y), nz(z), voxels(static_cast<std::size_t>(x) * y * z, fill) {}
  Volume(int x, int y, int z, int c, float fill)
      : nx(x), ny(y), nz(z), channels(c), voxels(static_cast<std::size_t>(x) * y * z * c, fill) {}
  // Any of the two: size = {nx, ny, nz, nt}.
  Volume(const std::array<int, 4>& size, int c, float fill)
      : nx(size[0]), ny(size[1]), nz(size[2]), channels(c),
        voxels(static_cast<std::size_t>(size[0]) * size[1] * size[2] * size[3] * c, fill), nt(size[3]) {}

  std::array<int, 4> size() const { return {nx, ny, nz, nt}; }
  std::size_t voxel_count() const { return static_cast<std::size_t>(nx) * ny * nz * nt; }
  bool empty() const { return voxels.empty(); }

  // The voxel's number (x fastest); its channel c is voxels[index * channels + c].
  std::size_t index(int x, int y, int z, int t = 0) const {
    return ((static_cast<std::size_t>(t) * nz + z) * ny + y) * nx + x;
  }
  // 3D access (time step 0) ...
  float& at(int x, int y, int z, int c = 0) { return voxels[index(x, y, z) * channels + c]; }
  float at(int x, int y, int z, int c = 0) const { return voxels[index(x, y, z) * channels + c]; }
  // ... and 4D access (named apart: at(x, y, z, c) takes a channel as its fourth argument).
  float& at4(int x, int y, int z, int t, int c = 0) { return voxels[index(x, y, z, t) * channels + c]; }
  float at4(int x, int y, int z, int t, int c = 0) const { return voxels[index(x, y, z, t) * channels + c]; }
};

// One channel of a volume as a scalar volume, and the channels put together
// again (the classic resamplers and pictures work on one channel).
inline Volume volume_channel(const Volume& v, int c) {
  Volume out(v.size(), 1, 0.0f);
  for (std::size_t i = 0; i < out.voxels.size(); ++i) out.voxels[i] = v.voxels[i * v.channels + c];
  return out;
}
inline void set_volume_channel(Volume& v, int c, const Volume& channel) {
  for (std::size_t i = 0; i < channel.voxels.size(); ++i) v.voxels[i * v.channels + c] = channel.voxels[i];
}

// Time step t of a volume series as a 3D volume (all channels).
inline Volume time_step(const Volume& v, int t) {
  Volume out(v.nx, v.ny, v.nz, v.channels, 0.0f);
  const std::size_t n = out.voxels.size();
  std::copy(v.voxels.begin() + t * n, v.voxels.begin() + (t + 1) * n, out.voxels.begin());
  return out;
}

}  // namespace ddt
