#pragma once
// Small builders shared by the 3D tests.

#include "mesh3.hpp"
#include "volume.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <set>
#include <vector>

namespace ddt::test {

// Voxel centres of an nx x ny x nz grid, x fastest (ids as in Volume::index).
inline std::vector<Point3> grid_points3(int nx, int ny, int nz) {
  std::vector<Point3> p;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) p.push_back({x + 0.5, y + 0.5, z + 0.5});
  return p;
}

inline std::vector<Point3> random_points3(int n, unsigned seed, double size = 10.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, size);
  std::vector<Point3> p(n);
  for (auto& q : p) q = {u(rng), u(rng), u(rng)};
  return p;
}

// The live tetrahedra as a set of sorted quadruples.
inline std::set<std::array<index_t, 4>> tet_set(const Mesh3& m) {
  std::set<std::array<index_t, 4>> s;
  for (index_t t = 0; t < m.slot_count(); ++t) {
    if (!m.is_live(t)) continue;
    std::array<index_t, 4> v = {m.tet[4 * t], m.tet[4 * t + 1], m.tet[4 * t + 2], m.tet[4 * t + 3]};
    std::sort(v.begin(), v.end());
    s.insert(v);
  }
  return s;
}

// A mesh from explicit tetrahedra (any orientation): orients them
// positively and glues faces with the same vertices. The naive builder the
// tests compare against.
inline Mesh3 mesh_from_tets(const std::vector<Point3>& points, std::vector<std::array<index_t, 4>> tets) {
  Mesh3 m;
  m.points = points;
  std::map<std::array<index_t, 3>, index_t> faces;
  m.opp.assign(4 * tets.size(), no_face);
  for (auto& t : tets) {
    if (orientation(points[t[0]], points[t[1]], points[t[2]], points[t[3]]) < 0) std::swap(t[0], t[1]);
    const index_t slot = static_cast<index_t>(m.tet.size() / 4);
    m.tet.insert(m.tet.end(), t.begin(), t.end());
    for (int i = 0; i < 4; ++i) {
      std::array<index_t, 3> key = {t[face_vertex[i][0]], t[face_vertex[i][1]], t[face_vertex[i][2]]};
      std::sort(key.begin(), key.end());
      auto it = faces.find(key);
      if (it == faces.end()) {
        faces[key] = 4 * slot + i;
      } else {
        m.opp[4 * slot + i] = it->second;
        m.opp[it->second] = 4 * slot + i;
      }
    }
  }
  return m;
}

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
