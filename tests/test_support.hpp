#pragma once
// Small builders shared by the tests.

#include "util/image.hpp"
#include "image/mesh.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <map>
#include <utility>
#include <array>
#include <random>
#include <set>
#include <vector>

namespace ddt::test {

// The benchmark data (Set5, Set14): $DDTSCALE_DATASETS if set, else the
// folder CMake was told (-DDDTSCALE_DATASETS_DIR, default ../shared/datasets
// beside the checkout). A clone without it skips the tests that need it.
inline std::string datasets_dir() {
  const char* env = std::getenv("DDTSCALE_DATASETS");
  return env && *env ? std::string(env) : std::string(DDTSCALE_DATASETS_DIR);
}

// A fresh directory under the system's temporary directory, removed with
// everything in it at the end of the scope; dir / "name" is a path in it.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "ddtscale-test-XXXXXX").string();
    path = mkdtemp(pattern.data());
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

inline std::vector<Point2> grid_points(int w, int h) {
  std::vector<Point2> p;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) p.push_back({x + 0.5, y + 0.5});
  return p;
}

// n x K values, uniform in [0, 1).
inline std::vector<float> random_values(std::size_t n, int K, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> v(n * K);
  for (auto& x : v) x = u(rng);
  return v;
}

inline std::vector<Point2> random_points(int n, unsigned seed, double size = 10.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, size);
  std::vector<Point2> p(n);
  for (auto& q : p) q = {u(rng), u(rng)};
  return p;
}

// The triangles as a set of rotated triples (smallest id first), so two
// meshes compare equal whatever their slot order.
inline std::set<std::array<index_t, 3>> triangle_set(const Mesh2& m) {
  std::set<std::array<index_t, 3>> s;
  for (index_t t = 0; t < m.triangle_count(); ++t) {
    std::array<index_t, 3> v = {m.tri[3 * t], m.tri[3 * t + 1], m.tri[3 * t + 2]};
    std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());
    s.insert(v);
  }
  return s;
}

// A mesh from explicit triangles (any orientation): orients them
// counter-clockwise and links twins. The naive builder the tests compare
// CGAL's result against.
inline Mesh2 mesh_from_triangles(const std::vector<Point2>& points, std::vector<std::array<index_t, 3>> tris) {
  Mesh2 m;
  m.points = points;
  std::map<std::pair<index_t, index_t>, index_t> directed;
  for (auto& t : tris) {
    if (orientation(points[t[0]], points[t[1]], points[t[2]]) < 0) std::swap(t[1], t[2]);
    for (int k = 0; k < 3; ++k) {
      const index_t e = static_cast<index_t>(m.tri.size());
      m.tri.push_back(t[k]);
      directed[{t[k], t[(k + 1) % 3]}] = e;
    }
  }
  m.opp.assign(m.tri.size(), no_edge);
  for (const auto& [edge, e] : directed) {
    auto twin = directed.find({edge.second, edge.first});
    if (twin != directed.end()) m.opp[e] = twin->second;
  }
  return m;
}

// The grid triangulation with every cell split along the same diagonal.
inline Mesh2 grid_mesh(int w, int h, bool slash) {
  std::vector<std::array<index_t, 3>> tris;
  for (int y = 0; y + 1 < h; ++y)
    for (int x = 0; x + 1 < w; ++x) {
      const index_t i00 = y * w + x, i10 = i00 + 1, i01 = i00 + w, i11 = i01 + 1;
      if (slash) {
        tris.push_back({i00, i10, i01});
        tris.push_back({i10, i11, i01});
      } else {
        tris.push_back({i00, i10, i11});
        tris.push_back({i00, i11, i01});
      }
    }
  return mesh_from_triangles(grid_points(w, h), tris);
}

// Image whose pixel (x, y) holds f(x + 0.5, y + 0.5) in every channel.
template <class F>
Image sampled_image(int w, int h, int channels, F f) {
  Image img(w, h, channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) img.at(x, y, c) = static_cast<float>(f(x + 0.5, y + 0.5, c));
  return img;
}

}  // namespace ddt::test
